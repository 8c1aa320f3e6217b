// `nightcap diff` as a CI gate: thresholds from a file (and where each came from), the last line
// of counts, JUnit XML (with --isolate's findings), exit codes, one frame of a multi-frame pair,
// and two scenes, where the frames' own inputs differ and no pass is the origin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "images/images.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kLight = std::string(kCity) + " --set lighting.tiled.intensity_scale=1.5";

std::string last_line(const std::string& text) {
  std::string trimmed = text;
  while (!trimmed.empty() && trimmed.back() == '\n') trimmed.pop_back();
  return trimmed.substr(trimmed.rfind('\n') == std::string::npos ? 0 : trimmed.rfind('\n') + 1);
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

TEST(DiffCi, ThresholdsFileHoldsWhatItMatchesAndSaysWhereFrom) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path dir = scratch("diff-thresholds");
  const fs::path file = dir / "thresholds.json";
  std::ofstream(file) << R"({"thresholds": [
    {"match": "lighting.*/*", "metric": "rel", "limit": 1e9},
    {"match": "tonemap/final.ldr", "metric": "flip", "limit": 1},
    {"match": "*", "metric": "abs", "limit": 1e30}]})";
  const CliResult r = run_cli("diff --json --thresholds " + quote(file) + " " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1) << "exposure's histogram, a buffer no 'abs' rule can measure, keeps its contract: " << r.err;
  const json diff = json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence"), (json{{"frame", 0}, {"pass", "lighting.tiled"}}));
  std::set<std::string> buffers;
  const Capture capture_a = Capture::open(a);
  for (const PassRecord& p : capture_a.frame(0).passes)
    for (const ResourceRecord& out : p.outputs)
      if (out.is_buffer) buffers.insert(out.resource);
  bool saw_lit = false, saw_ldr = false;
  for (const json& frame : diff.at("frames"))
    for (const json& p : frame.at("passes"))
      for (const json& o : p.at("outputs")) {
        ASSERT_TRUE(o.contains("held_to")) << o.dump();
        // Buffers fit no rule here ('abs', 'rel' and 'codes' measure images): they keep their contracts.
        const bool buffer = buffers.count(o.at("resource").get<std::string>()) > 0;
        EXPECT_NE(o.at("held_to").get<std::string>().find(buffer ? "(recorded contract)" : file.string() + " rule "),
                  std::string::npos)
            << o.dump();
        if (buffer) continue;
        EXPECT_FALSE(o.at("beyond").get<bool>()) << o.dump();
        if (o.at("resource") == "lighting.lit") {
          saw_lit = true;
          EXPECT_EQ(o.at("held_to"), "rel <= 1e+09 (" + file.string() + " rule 1)");
          EXPECT_GT(o.at("threshold").at("counted").get<uint64_t>(), 0u);
        }
        if (o.at("resource") == "final.ldr") {
          saw_ldr = true;
          EXPECT_EQ(o.at("held_to"), "flip <= 1 (" + file.string() + " rule 2)");
          // The displayed image gets FLIP whatever it is held to: brighter lights are visible.
          EXPECT_GT(o.at("flip").at("mean").get<double>(), 0.0);
          EXPECT_LE(o.at("flip").at("max").get<double>(), 1.0);
          EXPECT_EQ(o.at("threshold").at("worst").get<double>(), o.at("flip").at("max").get<double>());
        }
      }
  EXPECT_TRUE(saw_lit && saw_ldr);
  // --json owns stdout: the counts are the last line of stderr.
  EXPECT_TRUE(std::regex_match(last_line(r.err), std::regex("[0-9]+ passed, 2 failed")))
      << "the histogram of each frame: " << r.err;

  // The same pair without the file: the recorded contracts fail from lighting down.
  const CliResult plain = run_cli("diff " + quote(a) + " " + quote(b));
  EXPECT_EQ(plain.code, 1);
  std::smatch counts;
  const std::string line = last_line(plain.out);
  ASSERT_TRUE(std::regex_match(line, counts, std::regex("([0-9]+) passed, ([0-9]+) failed"))) << plain.out;
  EXPECT_GT(std::stoi(counts[2]), 0);
  EXPECT_NE(plain.out.find("(recorded contract)"), std::string::npos);
  EXPECT_NE(plain.out.find("FLIP mean "), std::string::npos) << "the table shows FLIP of the displayed image";
}

struct JunitCase {
  std::string suite, name, outcome, message;  // outcome: "passed", "failure" or "skipped"
};

// Text of an XML attribute or element as it was before escaping.
std::string unescaped(const std::string& xml) {
  std::string text;
  for (size_t i = 0; i < xml.size(); ++i) {
    bool entity = false;
    for (const auto& [name, c] :
         {std::pair{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&#39;", '\''}})
      if (xml.compare(i, std::strlen(name), name) == 0) {
        text += c;
        i += std::strlen(name) - 1;
        entity = true;
        break;
      }
    if (!entity) text += xml[i];
  }
  return text;
}

// The test cases of a JUnit file nightcap wrote, in order, their names and messages unescaped.
std::vector<JunitCase> junit_cases(const fs::path& file) {
  const std::string xml = slurp(file);
  const std::regex testcase(
      R"re(<testcase classname="([^"]*)" name="([^"]*)">\n\s*(?:<system-out>([^<]*)</system-out>|<(failure|skipped) message="([^"]*)"/>))re");
  std::vector<JunitCase> cases;
  for (auto m = std::sregex_iterator(xml.begin(), xml.end(), testcase); m != std::sregex_iterator(); ++m) {
    const std::smatch& c = *m;
    cases.push_back({unescaped(c[1]), unescaped(c[2]), c[4].matched ? c[4].str() : "passed",
                     unescaped(c[4].matched ? c[5].str() : c[3].str())});
  }
  EXPECT_EQ(cases.size(), count(xml, "<testcase ")) << "a test case the pattern does not read";
  return cases;
}

// The cases a diff of two captures of the same frames and passes must have, from their manifests:
// per frame, a pass skipped in both is one case, a pass that ran in both one per output of either.
std::multiset<std::pair<std::string, std::string>> expected_cases(const fs::path& a, const fs::path& b) {
  const json frames_a = read_json(a / "manifest.json").at("frames"),
             frames_b = read_json(b / "manifest.json").at("frames");
  EXPECT_EQ(frames_a.size(), frames_b.size());
  std::multiset<std::pair<std::string, std::string>> cases;
  for (size_t f = 0; f < frames_a.size() && f < frames_b.size(); ++f) {
    const std::string suite = "frame " + std::to_string(frames_a[f].at("index").get<int>());
    const json &passes_a = frames_a[f].at("passes"), &passes_b = frames_b[f].at("passes");
    EXPECT_EQ(passes_a.size(), passes_b.size());
    for (size_t p = 0; p < passes_a.size() && p < passes_b.size(); ++p) {
      const std::string pass = passes_a[p].at("name");
      EXPECT_EQ(passes_b[p].at("name"), pass);
      EXPECT_EQ(passes_a[p].at("status"), passes_b[p].at("status")) << pass;
      if (passes_a[p].at("status") == "skipped") {
        cases.insert({suite, pass});
        continue;
      }
      std::set<std::string> outputs;
      for (const json* passes : {&passes_a, &passes_b})
        for (const json& o : (*passes)[p].at("outputs")) outputs.insert(o.at("resource").get<std::string>());
      for (const std::string& o : outputs) cases.insert({suite, pass + "/" + o});
    }
  }
  return cases;
}

TEST(DiffCi, JunitHasOneCasePerPassAndOutputOfTheManifests) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path dir = scratch("diff-junit");
  const CliResult r = run_cli("diff --junit " + quote(dir / "diff.xml") + " " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1);
  const std::string xml = slurp(dir / "diff.xml");
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>", 0), 0u);
  const std::vector<JunitCase> cases = junit_cases(dir / "diff.xml");
  std::multiset<std::pair<std::string, std::string>> written;
  for (const JunitCase& c : cases) written.insert({c.suite, c.name});
  EXPECT_EQ(written, expected_cases(a, b));
  EXPECT_EQ(count(xml, "<testsuite "), 2u) << "one suite per frame";
  const auto stencil = std::find_if(cases.begin(), cases.end(), [](const JunitCase& c) {
    return c.suite == "frame 0" && c.name == "motion.stencil";
  });
  ASSERT_NE(stencil, cases.end()) << "motion.stencil is skipped in frame 0 of both";
  EXPECT_EQ(stencil->outcome, "skipped");
  EXPECT_EQ(stencil->message, "skipped in both captures");
  EXPECT_FALSE(fs::exists(dir / "diff.xml.partial"));
}

// --isolate adds to each differing output's case what running B's pass on A's inputs found, and
// changes no case and no outcome.
TEST(DiffCi, IsolateResultsAreInTheJunitFile) {
  const fs::path a = shared_capture("city", kCity),
                 b = shared_capture("city-light-bloom", kLight + " --set tonemap.bloom=0.1");
  const fs::path dir = scratch("diff-isolate-junit");
  const CliResult plain =
      run_cli("diff --frame 1 --junit " + quote(dir / "plain.xml") + " " + quote(a) + " " + quote(b));
  ASSERT_EQ(plain.code, 1) << plain.err;
  const CliResult isolated = run_cli("diff --json --isolate --frame 1 --junit " + quote(dir / "isolated.xml") + " " +
                                     quote(a) + " " + quote(b));
  ASSERT_EQ(isolated.code, 1) << isolated.err;
  std::map<std::string, std::string> summaries;  // pass -> what its isolation found
  std::map<std::string, bool> identical;         // PASS/RESOURCE -> identical
  const json isolated_diff = json::parse(isolated.out);
  for (const json& p : isolated_diff.at("frames").at(0).at("passes")) {
    if (p.contains("isolation")) summaries[p.at("name")] = p.at("isolation").at("summary");
    for (const json& o : p.at("outputs"))
      identical[p.at("name").get<std::string>() + "/" + o.at("resource").get<std::string>()] = o.at("identical");
  }
  ASSERT_TRUE(summaries.count("tonemap") && summaries.count("bloom.level0")) << isolated.out;
  const std::vector<JunitCase> before = junit_cases(dir / "plain.xml"), after = junit_cases(dir / "isolated.xml");
  ASSERT_EQ(before.size(), after.size());
  size_t with_isolation = 0;
  for (size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(after[i].suite, before[i].suite);
    EXPECT_EQ(after[i].name, before[i].name);
    EXPECT_EQ(after[i].outcome, before[i].outcome) << after[i].name;
    const std::string pass = after[i].name.substr(0, after[i].name.find('/'));
    const bool differs = identical.count(after[i].name) && !identical.at(after[i].name);
    const std::string added = summaries.count(pass) && differs ? "; " + summaries.at(pass) : "";
    EXPECT_EQ(after[i].message, before[i].message + added) << after[i].name;
    with_isolation += !added.empty();
  }
  EXPECT_GT(with_isolation, 0u);
  const auto tonemap =
      std::find_if(after.begin(), after.end(), [](const JunitCase& c) { return c.name == "tonemap/final.ldr"; });
  ASSERT_NE(tonemap, after.end());
  EXPECT_NE(tonemap->message.find("the pass itself changed"), std::string::npos) << tonemap->message;
}

// Two scenes: every pass differs with unequal inputs, so none is the origin. The diff names the
// frame whose own inputs differ and which, with the settings that differ, in the JSON, the table
// and the JUnit file.
TEST(DiffCi, DifferentScenesNameTheFrameInputsThatDiffer) {
  const fs::path a = shared_capture("city", kCity),
                 b = shared_capture("city-seed-2", std::string(kCity) + " --scene-seed 2");
  const fs::path dir = scratch("diff-scenes");
  const CliResult r = run_cli("diff --json --junit " + quote(dir / "diff.xml") + " " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.code, 1) << r.err;
  const json diff = json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence"), nullptr);
  // The reference, from the manifests: what frame 0's passes read that none of them writes, and
  // whose hash differs (the two scenes run the same passes).
  auto own_inputs = [](const fs::path& capture) {
    const json passes = read_json(capture / "manifest.json").at("frames").at(0).at("passes");
    std::set<std::string> written;
    for (const json& p : passes)
      for (const json& o : p.at("outputs")) written.insert(o.at("resource").get<std::string>());
    std::map<std::string, std::string> inputs;
    for (const json& p : passes)
      if (p.at("status") == "ran")
        for (const json& i : p.at("inputs"))
          if (!written.count(i.at("resource").get<std::string>())) inputs[i.at("resource")] = i.at("hash");
    return inputs;
  };
  for (const json& frame : diff.at("frames"))
    for (const json& p : frame.at("passes"))
      EXPECT_TRUE(p.at("status") == "inherited" || p.at("status") == "identical" || p.at("status") == "skipped")
          << p.dump();
  const auto inputs_a = own_inputs(a), inputs_b = own_inputs(b);
  json expected = json::array();
  for (const auto& [resource, hash] : inputs_a)
    if (!inputs_b.count(resource) || inputs_b.at(resource) != hash) expected.push_back(resource);
  EXPECT_EQ(inputs_a.size(), inputs_b.size());
  EXPECT_NE(std::find(expected.begin(), expected.end(), "scene.instances"), expected.end()) << expected.dump();
  EXPECT_EQ(diff.at("input_divergence"), (json{{"frame", 0}, {"inputs", expected}}));
  EXPECT_EQ(diff.at("frames").at(0).at("inputs_differ"), expected);
  EXPECT_EQ(diff.at("settings_differ"), json::array({"scene_seed"}));
  const json& scene = diff.at("scene_differ");
  EXPECT_NE(std::find(scene.begin(), scene.end(), "source"), scene.end()) << scene.dump();

  bool named = false;
  for (const JunitCase& c : junit_cases(dir / "diff.xml"))
    if (c.suite == "frame 0" && c.name == "frame inputs") {
      named = true;
      EXPECT_EQ(c.outcome, "failure");
      EXPECT_NE(c.message.find("scene.instances"), std::string::npos) << c.message;
      EXPECT_NE(c.message.find("the captures' settings differ: scene_seed"), std::string::npos) << c.message;
    }
  EXPECT_TRUE(named) << slurp(dir / "diff.xml");

  const CliResult table = run_cli("diff " + quote(a) + " " + quote(b));
  EXPECT_EQ(table.code, 1);
  EXPECT_NE(table.out.find("first divergence: the own inputs of frame 0 ("), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("  the frame's own inputs differ: "), std::string::npos) << table.out;

  // One scene with another lighting parameter: the frames' own inputs agree, and a pass is the origin.
  const json same_scene =
      json::parse(run_cli("diff --json " + quote(a) + " " + quote(shared_capture("city-light", kLight))).out);
  EXPECT_EQ(same_scene.at("input_divergence"), nullptr);
  EXPECT_EQ(same_scene.at("settings_differ"), json::array({"set"}));
  EXPECT_EQ(same_scene.at("scene_differ"), json::array());
  for (const json& frame : same_scene.at("frames")) EXPECT_EQ(frame.at("inputs_differ"), json::array());
}

// One scene seen from another camera: frame.camera is the one input of each frame that differs
// (frame 1's history comes from frame 0, which both captures hold, so it is not the frame's own).
TEST(DiffCi, AnotherCameraNamesFrameCameraAlone) {
  const fs::path a = shared_capture("city", kCity),
                 b = shared_capture("city-orbit", std::string(kCity) + " --orbit 30,20,40");
  const CliResult r = run_cli("diff --json " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.code, 1) << r.err;
  const json diff = json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence"), nullptr);
  EXPECT_EQ(diff.at("input_divergence"), (json{{"frame", 0}, {"inputs", json::array({"frame.camera"})}}));
  ASSERT_EQ(diff.at("frames").size(), 2u);
  for (const json& frame : diff.at("frames")) EXPECT_EQ(frame.at("inputs_differ"), json::array({"frame.camera"}));
  EXPECT_EQ(diff.at("settings_differ"), json::array({"orbit"}));
  EXPECT_EQ(diff.at("scene_differ"), json::array());
}

TEST(DiffCi, OneFrameOfAMultiFramePair) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const CliResult r = run_cli("diff --json --frame 1 " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1);
  const json diff = json::parse(r.out);
  ASSERT_EQ(diff.at("frames").size(), 1u);
  EXPECT_EQ(diff.at("frames")[0].at("index"), 1);
  EXPECT_EQ(diff.at("first_divergence"), (json{{"frame", 1}, {"pass", "lighting.tiled"}}));
  const CliResult missing = run_cli("diff --frame 7 " + quote(a) + " " + quote(b));
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("no frame 7"), std::string::npos) << missing.err;
}

TEST(DiffCi, ABadThresholdsFileIsAnError) {
  const fs::path a = shared_capture("city", kCity);
  const fs::path dir = scratch("diff-bad-thresholds");
  std::ofstream(dir / "t.json") << R"({"thresholds": [{"match": "*", "metric": "ssim", "limit": 1}]})";
  const CliResult r = run_cli("diff --thresholds " + quote(dir / "t.json") + " " + quote(a) + " " + quote(a));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find((dir / "t.json").string() + ": rule 1: 'metric' must be one of"), std::string::npos) << r.err;
  EXPECT_EQ(count(r.err, "\n"), 1u) << "one line: " << r.err;
}

// idiff's output for two image files, as text (it exits 2 when they differ).
std::string idiff(const fs::path& a, const fs::path& b) {
  const std::string command = "idiff -fail 0 -warn 0 " + quote(a) + " " + quote(b) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return "";
  std::string text;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) text.append(buffer, n);
  pclose(pipe);
  return text;
}

double idiff_figure(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return NAN;
  return std::stod(m[1]);
}

// Where the metrics overlap OpenImageIO's idiff (max abs error, RMS error over every channel,
// pixels that differ at all), both read the same blob files and agree. The blobs are EXR, which
// idiff reads as they are.
TEST(DiffCi, MetricsAgreeWithIdiffWhereTheyOverlap) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const CliResult r = run_cli("diff --json --frame 0 " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.code, 1) << r.err;
  const json diff = json::parse(r.out);
  const Capture capture_a = Capture::open(a), capture_b = Capture::open(b);
  int compared = 0;
  for (const json& p : diff.at("frames").at(0).at("passes"))
    for (const json& o : p.at("outputs")) {
      const std::string resource = o.at("resource");
      if (resource != "lighting.diffuse" && resource != "lighting.specular" && resource != "lighting.lit") continue;
      const ResourceRecord& ra = output_named(pass_named(capture_a.frame(0), p.at("name")), resource);
      const ResourceRecord& rb = output_named(pass_named(capture_b.frame(0), p.at("name")), resource);
      const std::string text = idiff(a / ra.blob, b / rb.blob);
      const double max_error = idiff_figure(text, R"(Max error\s*=\s*([0-9.eE+-]+))");
      const double rms = idiff_figure(text, R"(RMS error\s*=\s*([0-9.eE+-]+))");
      const double over = idiff_figure(text, R"(\n\s*([0-9]+) pixels \([0-9.]+%\) over 0)");
      ASSERT_TRUE(std::isfinite(max_error) && std::isfinite(rms) && std::isfinite(over)) << text;
      EXPECT_GT(max_error, 0.0) << resource;
      EXPECT_NEAR(o.at("max_abs").get<double>(), max_error, 1e-5 * max_error) << resource << "\n" << text;
      EXPECT_NEAR(o.at("rmse").get<double>(), rms, 1e-5 * rms) << resource << "\n" << text;
      EXPECT_EQ(o.at("differing").get<double>(), over) << resource << "\n" << text;
      ++compared;
    }
  EXPECT_EQ(compared, 3);
}

// --flip-maps writes the error map of the displayed image, one pixel per pixel, and names it.
TEST(DiffCi, FlipMapsAreWrittenAndNamed) {
  const fs::path a = shared_capture("city", kCity), b = shared_capture("city-light", kLight);
  const fs::path maps = scratch("diff-flip-maps") / "maps";
  const CliResult r = run_cli("diff --json --flip-maps " + quote(maps) + " " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.code, 1) << r.err;
  std::set<std::string> named;
  const json diff = json::parse(r.out);
  for (const json& frame : diff.at("frames"))
    for (const json& p : frame.at("passes"))
      for (const json& o : p.at("outputs"))
        if (o.contains("flip")) {
          const fs::path file = o.at("flip").at("map").get<std::string>();
          EXPECT_EQ(file.parent_path(), maps);
          const Rgba8Image image = decode_image_file(file, 4096);
          EXPECT_EQ(image.width, 320u);
          EXPECT_EQ(image.height, 180u);
          named.insert(file.filename().string());
        }
  EXPECT_EQ(named, (std::set<std::string>{"f0.tonemap.final.ldr.flip.png", "f1.tonemap.final.ldr.flip.png"}));
  std::set<std::string> written;
  for (const auto& entry : fs::directory_iterator(maps)) written.insert(entry.path().filename().string());
  EXPECT_EQ(written, named) << "nothing else, no partial files";
}

// B changes two passes: lighting.tiled's intensity (where the difference starts) and
// tonemap's bloom weight, behind it, whose inputs differ anyway. Only --isolate sees the second.
TEST(DiffCi, IsolateTellsAPassThatChangedFromOneWhoseInputsChanged) {
  const fs::path a = shared_capture("city", kCity),
                 b = shared_capture("city-light-bloom", kLight + " --set tonemap.bloom=0.1");
  const CliResult r = run_cli("diff --json --isolate --frame 1 " + quote(a) + " " + quote(b));
  ASSERT_EQ(r.code, 1) << r.err;
  const json diff = json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence"), (json{{"frame", 1}, {"pass", "lighting.tiled"}}));
  EXPECT_EQ(diff.at("changed_passes"),
            (json{{{"frame", 1}, {"pass", "lighting.tiled"}}, {{"frame", 1}, {"pass", "tonemap"}}}));
  std::set<std::string> isolated;
  for (const json& p : diff.at("frames").at(0).at("passes")) {
    const std::string status = p.at("status");
    if (status != "origin" && status != "inherited") {
      EXPECT_FALSE(p.contains("isolation")) << p.dump();
      continue;
    }
    const json& isolation = p.at("isolation");
    isolated.insert(p.at("name"));
    EXPECT_TRUE(isolation.at("ran").get<bool>()) << isolation.dump();
    const bool changed = p.at("name") == "lighting.tiled" || p.at("name") == "tonemap";
    EXPECT_EQ(isolation.at("pass_changed").get<bool>(), changed) << p.dump();
    if (p.at("name") == "tonemap") {
      EXPECT_EQ(status, "inherited") << "its inputs differ, so the plain diff cannot tell";
      EXPECT_EQ(isolation.at("outputs").at("final.ldr").get<std::string>().rfind("different", 0), 0u)
          << isolation.dump();
    }
    if (!changed) {
      for (const auto& [resource, made] : isolation.at("outputs").items())
        EXPECT_NE(made.get<std::string>().rfind("different", 0), 0u) << resource << ": " << made;
    }
  }
  EXPECT_TRUE(isolated.count("bloom.level0") && isolated.count("exposure") && isolated.count("tonemap"))
      << "every pass below lighting differs and is isolated";

  const CliResult table = run_cli("diff --isolate --frame 1 " + quote(a) + " " + quote(b));
  EXPECT_NE(table.out.find("the pass itself changed"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("the difference came through its inputs"), std::string::npos) << table.out;
  // Without --isolate nothing is run, and the JSON says nothing of it.
  EXPECT_FALSE(
      json::parse(run_cli("diff --json --frame 1 " + quote(a) + " " + quote(b)).out).contains("changed_passes"));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
