// `nightcap report` end to end: the folder it writes (every pass of the frame with its pictures,
// the graph, the timings), what it refuses to overwrite, and a capture with hostile names shown
// as text with nothing written outside the report folder.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "reports/html.h"
#include "tests/e2e/browser.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kCity = "--city-block --size 320x180 --frames 2";  // as tests/e2e/graph_test.cpp

uint64_t folder_bytes(const fs::path& folder) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

struct ImageTag {
  std::string src;
  int width = 0, height = 0;
};

std::vector<ImageTag> images_of(const std::string& html) {
  static const std::regex img(R"re(<img src="([^"]*)" width="(\d+)" height="(\d+)")re");
  std::vector<ImageTag> images;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it)
    images.push_back({(*it)[1], std::stoi((*it)[2]), std::stoi((*it)[3])});
  return images;
}

TEST(Report, ShowsEveryPassOfTheFrameWithItsPicturesGraphAndTimings) {
  const fs::path capture = shared_capture("city", kCity);
  const fs::path out = scratch("report") / "city";
  const CliResult r = run_cli("report " + quote(capture) + " -o " + quote(out));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find((out / "index.html").string()), std::string::npos) << r.out;
  const std::string html = slurp(out / "index.html");
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  const nlohmann::json& frame = manifest.at("frames")[0];

  // Every pass has its section, in execution order; those that ran appear in the timing chart
  // (frame 0 skips motion.stencil: the camera has not moved yet).
  size_t at = 0, skipped = 0;
  for (const auto& p : frame.at("passes")) {
    const std::string name = p.at("name");
    const size_t section = html.find("data-pass=\"" + name + "\"", at);
    ASSERT_NE(section, std::string::npos) << name << " missing or out of order";
    at = section;
    const bool charted = html.find(">" + name + "</text>") != std::string::npos;
    if (p.at("status") == "ran")
      EXPECT_TRUE(charted) << name << " not in the timing chart";
    else
      EXPECT_FALSE(charted) << name << " skipped, yet in the timing chart";
    skipped += p.at("status") != "ran";
  }
  EXPECT_GT(skipped, 0u);
  // Each image input and output is pictured; each picture is a PNG of the size the page states
  // (or that size enlarged a whole number of times), inside the report folder.
  std::set<std::string> sources;
  for (const ImageTag& image : images_of(html)) {
    sources.insert(image.src);
    if (image.src == "graph.svg") continue;
    ASSERT_EQ(image.src.rfind("images/", 0), 0u) << image.src;
    auto file = OIIO::ImageInput::open((out / image.src).string());
    ASSERT_TRUE(file) << image.src;
    const OIIO::ImageSpec& spec = file->spec();
    EXPECT_LE(std::max(spec.width, spec.height), 256);
    EXPECT_EQ(image.width % spec.width, 0) << image.src;
    EXPECT_EQ(image.width / spec.width, image.height / spec.height) << image.src;
  }
  size_t image_resources = 0;
  for (const auto& p : frame.at("passes"))
    for (const char* side : {"inputs", "outputs"})
      for (const auto& res : p.at(side)) image_resources += res.contains("format");
  EXPECT_GT(image_resources, 10u);
  EXPECT_GT(sources.size(), 10u);  // distinct contents share a picture
  EXPECT_NE(html.find("<img class=\"graph\" src=\"graph.svg\""), std::string::npos);
  const std::string svg = slurp(out / "graph.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  for (const auto& p : frame.at("passes"))
    EXPECT_NE(svg.find(p.at("name").get<std::string>()), std::string::npos) << p.at("name");
  // GLSL, parameters, pipeline and sampler state of a pass, escaped into the page.
  for (const auto& p : frame.at("passes"))
    if (p.at("name") == "gbuffer.opaque") {
      ASSERT_FALSE(p.at("pipelines").empty());
      EXPECT_NE(html.find("<summary>Pipeline state</summary><pre>" + escape_markup(p.at("pipelines").dump(1))),
                std::string::npos);
      EXPECT_NE(html.find("<h5>Samplers</h5><pre>" + escape_markup(p.at("samplers").dump(1))), std::string::npos);
    }
  EXPECT_NE(html.find("GLSL: gbuffer/opaque.frag"), std::string::npos);
  EXPECT_NE(html.find("#version 460"), std::string::npos);
  EXPECT_NE(html.find("<th>intensity_scale</th>"), std::string::npos);
  EXPECT_LT(folder_bytes(out) * 5, folder_bytes(capture)) << "thumbnails too large";
  EXPECT_FALSE(fs::exists(out / "index.html.partial"));
}

// The page as a browser shows it: no console error, every pass's section laid out in order,
// every image loaded with a size.
void expect_loads_in_chromium(const fs::path& index, const nlohmann::json& frame, const fs::path& scratch) {
  const PageCheck page = check_page(index, scratch);
  EXPECT_TRUE(page.console_errors.empty()) << page.console_errors.front();
  ASSERT_EQ(page.sections.size(), frame.at("passes").size());
  for (size_t i = 0; i < page.sections.size(); ++i) {
    EXPECT_EQ(page.sections[i].pass, frame.at("passes")[i].at("name").get<std::string>());
    EXPECT_GT(page.sections[i].width, 0);
    EXPECT_GT(page.sections[i].height, 0);
  }
  EXPECT_GT(page.images.size(), 10u);
  for (const PageImage& image : page.images) {
    EXPECT_TRUE(image.complete) << image.src;
    EXPECT_GT(image.natural_width, 0) << image.src;
    EXPECT_GT(image.natural_height, 0) << image.src;
  }
}

TEST(Report, LoadsInChromiumWithEveryPassAndEveryImage) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path capture = shared_capture("city", kCity);
  const fs::path folder = scratch("report-browser");
  ASSERT_EQ(run_cli("report " + quote(capture) + " -o " + quote(folder / "report")).code, 0);
  expect_loads_in_chromium(folder / "report" / "index.html", read_json(capture / "manifest.json").at("frames")[0],
                           folder);
}

TEST(Report, FrameOptionPicksTheFrameAndRefusesOneNotRecorded) {
  const fs::path capture = shared_capture("city", kCity);
  const fs::path folder = scratch("report-frame");
  const CliResult second = run_cli("report " + quote(capture) + " --frame 1 -o " + quote(folder / "one"));
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(slurp(folder / "one" / "index.html").find(", frame 1</title>"), std::string::npos);
  const CliResult missing = run_cli("report " + quote(capture) + " --frame 7 -o " + quote(folder / "seven"));
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("--frame 7"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(folder / "seven"));
}

TEST(Report, OverwritesOnlyAnEarlierReportAndOnlyWithForce) {
  const fs::path capture = shared_capture("city", kCity);
  const fs::path folder = scratch("report-overwrite");
  fs::create_directories(folder / "notes");
  std::ofstream(folder / "notes" / "keep.txt") << "mine";
  const CliResult refused = run_cli("report " + quote(capture) + " -o " + quote(folder / "notes"));
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("not empty"), std::string::npos) << refused.err;
  const CliResult forced = run_cli("report " + quote(capture) + " --force -o " + quote(folder / "notes"));
  EXPECT_EQ(forced.code, 2);
  EXPECT_NE(forced.err.find("not one"), std::string::npos) << forced.err;
  EXPECT_EQ(slurp(folder / "notes" / "keep.txt"), "mine");
  EXPECT_FALSE(fs::exists(folder / "notes" / "index.html"));

  ASSERT_EQ(run_cli("report " + quote(capture) + " -o " + quote(folder / "report")).code, 0);
  EXPECT_EQ(run_cli("report " + quote(capture) + " -o " + quote(folder / "report")).code, 2);
  const CliResult again = run_cli("report " + quote(capture) + " --frame 1 --force -o " + quote(folder / "report"));
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(slurp(folder / "report" / "index.html").find(", frame 1</title>"), std::string::npos);
}

TEST(Report, ACorruptBlobIsNamedAndLeavesNothingBehind) {
  const fs::path folder = scratch("report-corrupt");
  const fs::path copy = folder / "capture";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  // An image frame 0 pictures: gbuffer.opaque's first output.
  fs::path blob;
  const nlohmann::json manifest = read_json(copy / "manifest.json");
  for (const auto& p : manifest.at("frames")[0].at("passes"))
    if (p.at("name") == "gbuffer.opaque") blob = copy / p.at("outputs")[0].at("blob").get<std::string>();
  ASSERT_TRUE(fs::is_regular_file(blob)) << blob;
  fs::resize_file(blob, 100);
  const CliResult r = run_cli("report " + quote(copy) + " -o " + quote(folder / "report"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(blob.string()), std::string::npos) << r.err;
  EXPECT_TRUE(!fs::exists(folder / "report") || fs::is_empty(folder / "report"));
  // So the same command runs again once the capture is mended, without --force.
  fs::remove_all(copy);
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  EXPECT_EQ(run_cli("report " + quote(copy) + " -o " + quote(folder / "report")).code, 0);
}

TEST(Report, HostileNamesAreShownAsTextAndNothingIsWrittenOutsideTheFolder) {
  const std::string scene_source = "<script>alert(\"scene\")</script> '../../escape'";
  const std::string pass_name = "x\"y<script>alert(1)<b>";  // a pass name has no '/'
  const std::string param_name = "<img src=x onerror=alert(2)>\"'../../p";
  const std::string reason = "skipped <i>because</i> \"../../r\"";
  const fs::path root = scratch("report-hostile");
  const fs::path copy = root / "capture";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  nlohmann::json manifest = read_json(copy / "manifest.json");
  manifest.at("scene")["source"] = scene_source;
  for (auto& p : manifest.at("frames")[0].at("passes")) {
    if (p.at("name") == "depth.convert") p["name"] = pass_name;
    if (p.at("name") == "lighting.tiled") p.at("params")[param_name] = 1.5;
    if (p.at("name") == "tonemap") {
      p["status"] = "skipped";
      p["reason"] = reason;
    }
  }
  write_json(copy / "manifest.json", manifest);
  const fs::path out = root / "out" / "report";
  const CliResult r = run_cli("report " + quote(copy) + " -o " + quote(out));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(out / "index.html");
  // Nothing from the capture became markup: the report has no scripts of its own, and the names
  // are there as escaped text.
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<img src=x"), std::string::npos);
  EXPECT_EQ(html.find("<i>because"), std::string::npos);
  EXPECT_EQ(html.find("alert(1)<b>"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&quot;scene&quot;)&lt;/script&gt; &#39;../../escape&#39;"),
            std::string::npos);
  EXPECT_NE(html.find("data-pass=\"x&quot;y&lt;script&gt;alert(1)&lt;b&gt;\""), std::string::npos);
  EXPECT_NE(html.find("<th>&lt;img src=x onerror=alert(2)&gt;&quot;&#39;../../p</th>"), std::string::npos);
  EXPECT_NE(html.find("skipped &lt;i&gt;because&lt;/i&gt; &quot;../../r&quot;"), std::string::npos);
  // Every file written is in the report folder: beside the capture, only the folder made for it.
  auto inside = [](const fs::path& path, const fs::path& folder) {
    const fs::path relative = fs::relative(path, folder);
    return !relative.empty() && *relative.begin() != "..";
  };
  std::set<std::string> around;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (!inside(entry.path(), copy) && !inside(entry.path(), out))
      around.insert(fs::relative(entry.path(), root).string());
  EXPECT_EQ(around, (std::set<std::string>{"out"}));

  // In a browser the pass names read as they were recorded.
  NIGHTCAP_REQUIRE_CHROMIUM();
  expect_loads_in_chromium(out / "index.html", manifest.at("frames")[0], root / "browser");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
