// `nightcap report A B` and `report --golden`: the first divergence at the top, every output
// that differs with its metrics, the threshold it was held to and its pictures, and the large
// view in a browser, whose readout must give the texel values the captures recorded.
#include <gtest/gtest.h>

#include <regex>
#include <set>

#include "captures/capture.h"
#include "reports/html.h"
#include "tests/e2e/browser.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kLight = std::string(kCity) + " --set lighting.tiled.intensity_scale=1.5";  // as diff_ci_test

// Opens lighting.diffuse large, points at texel (X, Y), zooms in, closes with Escape.
std::string use_the_viewer(uint32_t x, uint32_t y) {
  return R"((async () => {
  const until = async (ready) => { while (!ready()) await new Promise(r => setTimeout(r, 20)); };
  const card = document.querySelector('section.output[data-output-name="lighting.tiled/lighting.diffuse"]');
  card.querySelector('img[data-view="b"]').click();
  const viewer = document.getElementById('viewer');
  const img = viewer.querySelector('.stage img');
  const readout = viewer.querySelector('.readout');
  await until(() => img.complete && img.naturalWidth > 0 && !readout.textContent.startsWith('loading'));
  const box = img.getBoundingClientRect();
  const scale = box.width / img.naturalWidth;
  img.dispatchEvent(new MouseEvent('mousemove', {clientX: box.left + )" +
         std::to_string(x) + R"(.5 * scale, clientY: box.top + )" + std::to_string(y) + R"(.5 * scale, bubbles: true}));
  const text = readout.textContent;
  const before = box.width;
  viewer.querySelector('[data-zoom="in"]').click();
  const after = img.getBoundingClientRect().width;
  const open = !viewer.hidden;
  document.dispatchEvent(new KeyboardEvent('keydown', {key: 'Escape'}));
  return {readout: text, src: img.getAttribute('src'), zoomed: after > before, open, closed: viewer.hidden};
})())";
}

// lighting.tiled's lighting.diffuse in frame 0 of `folder`, decoded.
std::vector<float> diffuse_of(const fs::path& folder) {
  const Capture capture = Capture::open(folder);
  return decoded_output(capture, capture.frame(0), "lighting.tiled", "lighting.diffuse");
}

std::vector<double> numbers_after(const std::string& text, const std::string& label) {
  const size_t at = text.find(label);
  if (at == std::string::npos) return {};
  std::vector<double> values;
  std::istringstream rest(text.substr(at + label.size()));
  std::string item;
  while (values.size() < 4 && std::getline(rest, item, ',')) values.push_back(std::stod(item));
  return values;
}

TEST(DiffReport, ShowsTheFirstDivergenceAndEveryDifferingOutputWithWhatItWasHeldTo) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path out = scratch("diff-report") / "report";
  const CliResult r = run_cli("report " + quote(a) + " " + quote(b) + " -o " + quote(out));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(out / "index.html");
  EXPECT_NE(html.find("First divergence: <a href=\"#f0-lighting.tiled\">lighting.tiled</a>, frame 0"),
            std::string::npos);
  const CliResult diff = run_cli("diff --json " + quote(a) + " " + quote(b));
  ASSERT_EQ(diff.code, 1) << diff.err;
  size_t differing = 0;
  const json listing = json::parse(diff.out);
  for (const json& frame : listing.at("frames"))
    for (const json& pass : frame.at("passes"))
      for (const json& o : pass.value("outputs", json::array())) {
        if (o.value("identical", false)) continue;
        ++differing;
        const std::string name = pass.at("name").get<std::string>() + "/" + o.at("resource").get<std::string>();
        const size_t card = html.find("data-output-name=\"" + name + "\"");
        ASSERT_NE(card, std::string::npos) << name;
        const std::string section = html.substr(card, html.find("</section>", card) - card);
        EXPECT_NE(section.find("held to " + escape_markup(o.at("held_to").get<std::string>())), std::string::npos)
            << section;
        EXPECT_NE(section.find(o.at("beyond").get<bool>() ? ">beyond<" : ">within<"), std::string::npos) << section;
        if (o.contains("flip")) {
          EXPECT_NE(section.find("data-view=\"flip\""), std::string::npos) << name;
        }
      }
  EXPECT_GT(differing, 5u);
  // Each differing image's pictures, thumbnail and large, and the values of its large view.
  const std::regex picture(R"re(src="images/([0-9a-f]{16})\.(a|b|difference|flip)\.png")re");
  std::set<std::string> ids;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), picture); it != std::sregex_iterator(); ++it) {
    const std::string id = (*it)[1], view = (*it)[2];
    ids.insert(id);
    EXPECT_TRUE(fs::exists(out / "images" / (id + "." + view + ".png"))) << id << view;
    EXPECT_TRUE(fs::exists(out / "images" / (id + "." + view + ".large.png"))) << id << view;
  }
  EXPECT_GT(ids.size(), 5u);
  for (const std::string& id : ids) EXPECT_TRUE(fs::exists(out / "data" / (id + ".js"))) << id;
  // The same names on a second run, though outputs are measured in parallel.
  const fs::path again = out.parent_path() / "again";
  ASSERT_EQ(run_cli("report " + quote(a) + " " + quote(b) + " -o " + quote(again)).code, 0);
  EXPECT_EQ(slurp(again / "index.html"), html);
}

TEST(DiffReport, LargeViewReadsOutTheRecordedValuesOfBothCaptures) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path folder = scratch("diff-report-browser");
  ASSERT_EQ(run_cli("report " + quote(a) + " " + quote(b) + " -o " + quote(folder / "report")).code, 0);
  // The texel where the captures differ most, so that the values read out are not zeros.
  const std::vector<float> diffuse_a = diffuse_of(a), diffuse_b = diffuse_of(b);
  ASSERT_EQ(diffuse_a.size(), 320u * 180u * 4u);
  ASSERT_EQ(diffuse_b.size(), diffuse_a.size());
  size_t worst = 0;
  for (size_t i = 0; i < diffuse_a.size(); ++i)
    if (std::abs(diffuse_b[i] - diffuse_a[i]) > std::abs(diffuse_b[worst] - diffuse_a[worst])) worst = i;
  const uint32_t x = uint32_t(worst / 4 % 320), y = uint32_t(worst / 4 / 320);
  const PageCheck page = check_page(folder / "report" / "index.html", folder, use_the_viewer(x, y));
  EXPECT_TRUE(page.console_errors.empty()) << page.console_errors.front();
  // A section per pass of each frame, frame after frame.
  std::vector<std::string> passes;
  const json manifest = read_json(a / "manifest.json");
  for (const json& frame : manifest.at("frames"))
    for (const json& pass : frame.at("passes")) passes.push_back(pass.at("name"));
  ASSERT_EQ(page.sections.size(), passes.size());
  for (size_t i = 0; i < page.sections.size(); ++i) {
    EXPECT_EQ(page.sections[i].pass, passes[i]);
    EXPECT_GT(page.sections[i].height, 0);
  }
  for (const PageImage& image : page.images) EXPECT_GT(image.natural_width, 0) << image.src;

  const json& used = page.script_result;
  ASSERT_TRUE(used.is_object()) << used.dump();
  EXPECT_TRUE(used.at("open").get<bool>());
  EXPECT_TRUE(used.at("zoomed").get<bool>());
  EXPECT_TRUE(used.at("closed").get<bool>());
  const std::string readout = used.at("readout").get<std::string>();
  // 320 texels across fit the large view: each of its pixels is the texel at the same place.
  EXPECT_NE(readout.find("texel (" + std::to_string(x) + ", " + std::to_string(y) + ")"), std::string::npos) << readout;
  for (const auto& [label, recorded] : {std::pair{"A: ", &diffuse_a}, std::pair{"B: ", &diffuse_b}}) {
    const std::vector<double> shown = numbers_after(readout, label);
    ASSERT_EQ(shown.size(), 4u) << readout;
    for (size_t c = 0; c < 4; ++c) {
      const double value = (*recorded)[(size_t(y) * 320 + x) * 4 + c];
      // Five significant digits, as the page prints them.
      EXPECT_NEAR(shown[c], value, 1e-4 * std::max(1.0, std::abs(value))) << label << c << " " << readout;
    }
  }
  EXPECT_GT(std::abs(diffuse_b[worst] - diffuse_a[worst]), 0.1f);
}

TEST(DiffReport, AgainstAGoldenOfAStore) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path folder = scratch("diff-report-golden");
  const fs::path store = folder / "store";
  const CliResult missing =
      run_cli("report --golden city --store " + quote(store) + " " + quote(b) + " -o " + quote(folder / "none"));
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("golden 'city' missing from store"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(folder / "none"));
  ASSERT_EQ(run_cli("golden update " + quote(a) + " --store " + quote(store) + " --name city").code, 0);
  const CliResult r =
      run_cli("report --golden city --store " + quote(store) + " " + quote(b) + " -o " + quote(folder / "report"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(folder / "report" / "index.html");
  EXPECT_NE(html.find("Diff of <span class=\"name\">golden</span>"), std::string::npos);
  EXPECT_NE(html.find("First divergence: <a href=\"#f0-lighting.tiled\">"), std::string::npos);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
