// `nightcap report` end to end: the folder it writes (every pass of the frame with its pictures,
// the graph, the timings), what it refuses to overwrite, and a capture with hostile names shown
// as text with nothing written outside the report folder.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>

#include "captures/capture.h"
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
  const size_t chart_start = html.find("<svg class=\"timings\"");
  ASSERT_NE(chart_start, std::string::npos);
  const std::string chart = html.substr(chart_start, html.find("</svg>", chart_start) - chart_start);
  for (const auto& p : frame.at("passes")) {
    const std::string name = p.at("name");
    const size_t section = html.find("data-pass=\"" + name + "\"", at);
    ASSERT_NE(section, std::string::npos) << name << " missing or out of order";
    at = section;
    const bool charted = chart.find(">" + name + "</text>") != std::string::npos;
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
  EXPECT_NE(html.find("<a href=\"graph.svg\">graph.svg</a>"), std::string::npos);
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

// The figure of `resource` where the page first shows it, up to its end.
std::string figure_of(const std::string& html, const std::string& resource) {
  const size_t at = html.find("data-resource=\"" + resource + "\"");
  if (at == std::string::npos) return "";
  return html.substr(at, html.find("</figure>", at) - at);
}

const ResourceRecord& output_of(const FrameRecord& frame, const std::string& resource) {
  for (const PassRecord& p : frame.passes)
    for (const ResourceRecord& r : p.outputs)
      if (r.resource == resource) return r;
  throw std::runtime_error("no output " + resource);
}

// The components of a schema field, read from the buffer's bytes here rather than by inspect's
// decoding: integers as their decimal text, floats as their value.
struct Component {
  bool integer = false;
  std::string text;
  double value = 0;
};
std::vector<Component> components(const std::vector<uint8_t>& raw, uint64_t element, uint32_t stride,
                                  const SchemaField& field) {
  std::vector<Component> out;
  for (uint32_t c = 0; c < field.count; ++c) {
    const uint8_t* at = raw.data() + element * stride + field.offset + c * (field.scalar == Scalar::f64 ? 8 : 4);
    Component component;
    if (field.scalar == Scalar::u32 || field.scalar == Scalar::i32) {
      uint32_t u;
      std::memcpy(&u, at, 4);
      component = {true, field.scalar == Scalar::u32 ? std::to_string(u) : std::to_string(int32_t(u))};
    } else if (field.scalar == Scalar::f32) {
      float f;
      std::memcpy(&f, at, 4);
      component.value = f;
    } else
      std::memcpy(&component.value, at, 8);
    out.push_back(component);
  }
  return out;
}

// `shown` (a table cell: a value, or values in parentheses) holds exactly the components: floats
// read back to the same float or double, bit for bit.
void expect_shows(const std::string& shown, const std::vector<Component>& expected, const SchemaField& field,
                  const std::string& where) {
  std::string text = shown;
  if (field.count > 1) {
    ASSERT_TRUE(text.size() > 2 && text.front() == '(' && text.back() == ')') << where << ": " << shown;
    text = text.substr(1, text.size() - 2);
  }
  std::vector<std::string> parts;
  for (size_t from = 0;;) {
    const size_t comma = text.find(", ", from);
    parts.push_back(text.substr(from, comma - from));
    if (comma == std::string::npos) break;
    from = comma + 2;
  }
  ASSERT_EQ(parts.size(), expected.size()) << where << ": " << shown;
  for (size_t c = 0; c < parts.size(); ++c) {
    if (expected[c].integer) {
      EXPECT_EQ(parts[c], expected[c].text) << where << "[" << c << "]";
    } else if (field.scalar == Scalar::f32) {
      const float read = std::strtof(parts[c].c_str(), nullptr), stored = float(expected[c].value);
      EXPECT_EQ(std::memcmp(&read, &stored, 4), 0) << where << "[" << c << "]: " << parts[c] << " vs " << stored;
    } else {
      const double read = std::strtod(parts[c].c_str(), nullptr);
      EXPECT_EQ(std::memcmp(&read, &expected[c].value, 8), 0) << where << "[" << c << "]: " << parts[c];
    }
  }
}

// What the cell after `<th>NAME</th>` in `html` holds.
std::string cell_after(const std::string& html, const std::string& name) {
  const std::string head = "<th>" + name + "</th><td>";
  const size_t at = html.find(head);
  if (at == std::string::npos) return "";
  const size_t from = at + head.size();
  return html.substr(from, html.find("</td>", from) - from);
}

// The nearest and farthest texel of `layers` layers of a one-channel float depth image (the depth
// plane of a depth-stencil one) that `draw` keeps (nothing drawn: it gives 0), as the caption
// prints them.
std::string range_of(const std::vector<uint8_t>& raw, const ResourceRecord& r, uint32_t layers,
                     const std::function<double(float)>& draw) {
  const size_t texels = size_t(r.extent.width) * r.extent.height * layers;
  double nearest = INFINITY, farthest = 0;
  for (size_t i = 0; i < texels; ++i) {
    float d;
    std::memcpy(&d, raw.data() + 4 * i, 4);
    const double shown = draw(d);
    if (!std::isfinite(shown) || shown <= 0) continue;
    nearest = std::min(nearest, shown);
    farthest = std::max(farthest, shown);
  }
  return "<span class=\"range\">" + format_number(nearest) + " … " + format_number(farthest) + "</span>";
}

// Buffers are shown by their recorded schemas, with values read from their blobs here: a record
// as its fields, a list as its count and first entries, a draw list as its draws and triangles.
// Depth and shadow maps are drawn between the nearest and farthest depth present, which the
// caption states, and every layer of a shadow map array is a picture of its own.
TEST(Report, ShowsBuffersByTheirSchemaAndDepthByItsRangeAndEveryLayerOfAShadowMap) {
  const fs::path folder = shared_capture("city", kCity);
  const fs::path out = scratch("report-pictures") / "city";
  ASSERT_EQ(run_cli("report " + quote(folder) + " -o " + quote(out)).code, 0);
  const std::string html = slurp(out / "index.html");
  const Capture capture = Capture::open(folder);
  const FrameRecord& frame = capture.frame(0);

  for (const char* name : {"frame.constants", "cull.stats", "lights.cluster_stats"}) {
    const ResourceRecord& r = output_of(frame, name);
    ASSERT_TRUE(r.schema) << name;
    ASSERT_EQ(r.buffer_size, r.schema->stride) << name << " is a record";
    const std::string figure = figure_of(html, name);
    ASSERT_NE(figure.find("<table class=\"record\">"), std::string::npos) << name;
    const std::vector<uint8_t> raw = capture.load(r);
    for (const SchemaField& field : r.schema->fields)
      expect_shows(cell_after(figure, field.name), components(raw, 0, r.schema->stride, field), field,
                   std::string(name) + "." + field.name);
  }

  const ResourceRecord& lights = output_of(frame, "frame.lights");
  const uint64_t light_count = lights.buffer_size / lights.schema->stride;
  ASSERT_GT(light_count, 8u);
  const std::string lights_figure = figure_of(html, "frame.lights");
  EXPECT_NE(
      lights_figure.find(std::to_string(light_count) + " elements of " + std::to_string(lights.schema->stride) + " B"),
      std::string::npos)
      << lights_figure;
  EXPECT_NE(lights_figure.find("… " + std::to_string(light_count - 8) + " more"), std::string::npos);
  const SchemaField& first_field = lights.schema->fields.front();
  const size_t row = lights_figure.find("<tr><th>0</th><td>");
  ASSERT_NE(row, std::string::npos);
  const size_t value = row + std::string("<tr><th>0</th><td>").size();
  expect_shows(lights_figure.substr(value, lights_figure.find("</td>", value) - value),
               components(capture.load(lights), 0, lights.schema->stride, first_field), first_field,
               "frame.lights[0]." + first_field.name);
  EXPECT_EQ(lights_figure.find("<tr><th>8</th>"), std::string::npos) << "only the first 8 entries";

  for (const char* name : {"draws.depth.prepass", "draws.shadow.cascades"}) {
    const ResourceRecord& r = output_of(frame, name);
    uint32_t index_count_at = 0;
    for (const SchemaField& field : r.schema->fields)
      if (field.name == "index_count") index_count_at = field.offset;
    ASSERT_GT(index_count_at, 0u) << name;
    const std::vector<uint8_t> raw = capture.load(r);
    const uint64_t draws = raw.size() / r.schema->stride;
    uint64_t triangles = 0;
    for (uint64_t d = 0; d < draws; ++d) {
      uint32_t indices;
      std::memcpy(&indices, raw.data() + d * r.schema->stride + index_count_at, 4);
      triangles += indices / 3;
    }
    EXPECT_GT(draws, 0u) << name;
    EXPECT_NE(
        figure_of(html, name).find(std::to_string(draws) + " draws · " + std::to_string(triangles) + " triangles"),
        std::string::npos)
        << figure_of(html, name);
  }

  // A buffer without a schema: its size.
  const ResourceRecord& occlusion = output_of(frame, "cull.occlusion");
  ASSERT_FALSE(occlusion.schema);
  EXPECT_NE(figure_of(html, "cull.occlusion").find(std::to_string(occlusion.buffer_size) + " bytes</div>"),
            std::string::npos);

  // Reversed-Z device depth d is znear / distance, and 0 where nothing was drawn: the caption
  // states the distances drawn.
  const ResourceRecord& depth = output_of(frame, "scene.depth");
  const double znear = frame.camera.znear;
  EXPECT_NE(figure_of(html, "scene.depth")
                .find(range_of(capture.load(depth), depth, 1, [&](float d) { return d > 0 ? znear / d : 0.0; })),
            std::string::npos)
      << figure_of(html, "scene.depth");

  // The cascades: a picture per layer, labelled, all drawn between the depths their casters left
  // (1: none).
  const ResourceRecord& cascades = output_of(frame, "shadow.cascades");
  ASSERT_EQ(cascades.extent.layers, 4u);
  const std::string cascades_figure = figure_of(html, "shadow.cascades");
  std::set<std::string> layer_files;
  for (uint32_t layer = 0; layer < 4; ++layer) {
    const std::regex picture("<img src=\"([^\"]+)\"[^>]*alt=\"shadow.cascades layer " + std::to_string(layer) +
                             "\"><span class=\"layer-index\">" + std::to_string(layer) + "</span>");
    std::smatch found;
    ASSERT_TRUE(std::regex_search(cascades_figure, found, picture)) << "layer " << layer << ": " << cascades_figure;
    layer_files.insert(found[1]);
    EXPECT_TRUE(fs::is_regular_file(out / found[1].str())) << found[1];
  }
  EXPECT_EQ(layer_files.size(), 4u);
  EXPECT_NE(cascades_figure.find(
                range_of(capture.load(cascades), cascades, 4, [](float d) { return d < 1.0f ? double(d) : 0.0; })),
            std::string::npos)
      << cascades_figure;
  // Local shadow maps, 16 layers: the first 8, and how many more there are.
  const ResourceRecord& local = output_of(frame, "shadow.local");
  ASSERT_EQ(local.extent.layers, 16u);
  const std::string local_figure = figure_of(html, "shadow.local");
  EXPECT_NE(local_figure.find("alt=\"shadow.local layer 7\""), std::string::npos);
  EXPECT_EQ(local_figure.find("alt=\"shadow.local layer 8\""), std::string::npos);
  EXPECT_NE(local_figure.find("… 8 more layers"), std::string::npos);
  // The GI volume: 8 slices of its cells' first texels (of 64 cells along z, each cell 7 blocks
  // of slices deep), labelled, and the caption says which.
  const ResourceRecord& volume = output_of(frame, "gi.volume");
  ASSERT_EQ(volume.extent.depth, 7u * 64u);
  const std::string volume_figure = figure_of(html, "gi.volume");
  for (uint32_t slice = 0; slice < 64; slice += 8)
    EXPECT_NE(volume_figure.find("alt=\"gi.volume slice " + std::to_string(slice) +
                                 "\"><span class=\"layer-index\">slice " + std::to_string(slice) + "</span>"),
              std::string::npos)
        << slice << ": " << volume_figure;
  EXPECT_NE(volume_figure.find("slices 0, 8, 16, 24, 32, 40, 48, 56 of 64 (each cell's first texel)"),
            std::string::npos)
      << volume_figure;
  EXPECT_LT(folder_bytes(out) * 5, folder_bytes(folder)) << "thumbnails too large";
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
