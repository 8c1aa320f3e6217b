// `render --inject-nan` and `inspect`'s `nan`: the manifest records the injection, `nan` names
// the injected pass, resource and pixel (placed here by the scaling formula, not by inspect's
// code) and not the passes that read the NaN after it, searches every frame (an injection is
// made in each) or the current one, a clean capture has no origin, replay writes the NaN again,
// and bad flags and hostile manifests are refused with one line. The search's rules on frames
// built by hand, float depth and buffer fields included: tests/unit/nan_origin_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <sstream>

#include "captures/capture.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const char* kInjected = "--city-block --size 320x180 --inject-nan lighting.tiled:100,50";
// bloom.chain is half the output (160x90, with mips) and exposure.value 1x1.
const char* kScaled = "--city-block --size 320x180 --inject-nan bloom.level0:101,51 --inject-nan exposure:300,170";
const char* kTwoFrames = "--city-block --size 160x90 --frames 2 --inject-nan lighting.tiled:40,20";

json inspect_json(const fs::path& capture, const std::string& command) {
  const Inspected run = inspect(capture, command + " --json");
  EXPECT_EQ(run.result.code, 0) << run.result.err;
  return run.objects.at(0);
}

const json& pass_json(const json& manifest, const std::string& name) {
  for (const json& p : manifest.at("frames").at(0).at("passes"))
    if (p.at("name") == name) return p;
  throw std::runtime_error("no pass " + name);
}

bool half_is_nan(const std::vector<uint8_t>& raw, uint64_t offset) {
  const uint16_t h = uint16_t(raw[offset] | (raw[offset + 1] << 8));
  return ((h >> 10) & 31) == 31 && (h & 1023) != 0;
}

TEST(NanOrigin, ManifestRecordsTheInjectionInTexelsOfTheFirstFloatOutput) {
  const json manifest = read_json(shared_capture("nan-deferred", kInjected) / "manifest.json");
  EXPECT_EQ(pass_json(manifest, "lighting.tiled").at("injected_nan"),
            (json{{"resource", "lighting.diffuse"}, {"x", 100}, {"y", 50}}));
  EXPECT_FALSE(pass_json(manifest, "lighting.composite").contains("injected_nan"));
  EXPECT_EQ(manifest.at("settings").at("inject_nan"), json::array({"lighting.tiled:100,50"}));

  const json scaled = read_json(shared_capture("nan-scaled", kScaled) / "manifest.json");
  // Output pixel (101, 51) of 320x180 lands on texel (101·160/320, 51·90/180) of the half-size chain.
  EXPECT_EQ(pass_json(scaled, "bloom.level0").at("injected_nan"),
            (json{{"resource", "bloom.chain"}, {"x", 50}, {"y", 25}}));
  // exposure's first output is a buffer: its first float output is the 1x1 exposure.value.
  EXPECT_EQ(pass_json(scaled, "exposure").at("injected_nan"),
            (json{{"resource", "exposure.value"}, {"x", 0}, {"y", 0}}));
}

TEST(NanOrigin, NamesTheInjectedPassPixelAndItsInputsThere) {
  const fs::path path = shared_capture("nan-deferred", kInjected);
  const json j = inspect_json(path, "nan");
  ASSERT_TRUE(j.at("origin").is_object()) << j;
  EXPECT_EQ(j.at("frames"), json::array({0}));
  ASSERT_EQ(j.at("origins").size(), 1u) << "the passes after it read the NaN: " << j;
  const json& origin = j.at("origin");
  EXPECT_EQ(origin, j.at("origins")[0]);
  EXPECT_EQ(origin.at("how"), "born");
  EXPECT_EQ(origin.at("frame"), 0);
  EXPECT_EQ(origin.at("pass"), "lighting.tiled");
  ASSERT_EQ(origin.at("resources").size(), 1u) << "lighting.specular holds no NaN: " << origin;
  const json& output = origin.at("resources")[0];
  EXPECT_EQ(output.at("resource"), "lighting.diffuse");
  EXPECT_EQ(output.at("count"), 1);
  ASSERT_EQ(output.at("texels").size(), 1u);
  const json& texel = output.at("texels")[0];
  EXPECT_EQ(texel.at("pixel"), json::array({100, 50}));
  EXPECT_EQ(texel.at("texel"), json::array({100, 50}));
  EXPECT_EQ(texel.at("mip"), 0);
  EXPECT_EQ(texel.at("values"), json::array({"NaN", "NaN", "NaN", "NaN"}));

  // Every image input of the pass at that pixel but its LTC tables, which are not laid over the
  // screen; scene.depth's device depth read here from the D32_SFLOAT_S8 blob's depth plane.
  std::set<std::string> inputs;
  for (const json& in : texel.at("inputs")) inputs.insert(in.at("resource").get<std::string>());
  EXPECT_EQ(inputs, (std::set<std::string>{"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "scene.depth",
                                           "depth.linear", "lights.clusters", "shadow.sun"}));
  const Capture capture = Capture::open(path);
  const std::vector<uint8_t> depth =
      capture.load(input_named(pass_named(capture.frame(0), "lighting.tiled"), "scene.depth"));
  float expected = 0;
  std::memcpy(&expected, depth.data() + (50 * 320 + 100) * 4, 4);
  for (const json& in : texel.at("inputs"))
    if (in.at("resource") == "scene.depth") {
      EXPECT_EQ(in.at("texel"), json::array({100, 50}));
      EXPECT_EQ(in.at("raw")[0].get<double>(), double(expected));
    }

  const CliResult text = run_cli("inspect " + quote(path) + " -c 'nan'");
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("frame 0: 1 origin(s)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("the first NaN or Inf was written by frame 0, lighting.tiled"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("pixel (100, 50)"), std::string::npos) << text.out;
}

// The frame's passes do not compute a NaN from one they read (lighting.composite's limit to
// 65504 and bloom's filter drop it), but bloom.level1 … level5 modify bloom.chain and so carry the
// injected texel of mip 0 on in every version they write: each holds a NaN and none is named.
TEST(NanOrigin, APassThatCarriesTheNanOnIsNotItsOrigin) {
  const fs::path path = shared_capture("nan-scaled", kScaled);
  const Capture capture = Capture::open(path);
  for (int level = 1; level <= 5; ++level) {
    const std::string pass = "bloom.level" + std::to_string(level);
    const std::vector<uint8_t> chain = capture.load(output_named(pass_named(capture.frame(0), pass), "bloom.chain"));
    EXPECT_TRUE(half_is_nan(chain, (25 * 160 + 50) * 8)) << pass << " does not carry the NaN";
  }
  const CliResult r = run_cli("inspect " + quote(path) + " -c 'goto tonemap; nan --json'");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out.substr(r.out.find('\n') + 1));
  EXPECT_EQ(j.at("origin").at("pass"), "bloom.level0") << "from any current pass";
  // exposure's injection is the other origin: it reads bloom.chain's mip 5 and taa.resolved,
  // which hold no NaN (bloom.chain's is in mip 0).
  std::vector<std::string> origins;
  for (const json& o : j.at("origins")) origins.push_back(o.at("pass"));
  EXPECT_EQ(origins, (std::vector<std::string>{"bloom.level0", "exposure"})) << j;

  const Capture deferred = Capture::open(shared_capture("nan-deferred", kInjected));
  const std::vector<uint8_t> diffuse =
      deferred.load(input_named(pass_named(deferred.frame(0), "lighting.composite"), "lighting.diffuse"));
  EXPECT_TRUE(half_is_nan(diffuse, (50 * 320 + 100) * 8)) << "lighting.composite reads the NaN";
}

TEST(NanOrigin, ACleanCaptureHasNoOrigin) {
  const fs::path path = shared_capture("city", kCity);
  EXPECT_EQ(inspect_json(path, "nan").at("origin"), nullptr);
  const CliResult text = run_cli("inspect " + quote(path) + " -c 'nan'");
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("no pass wrote a NaN or an Inf"), std::string::npos) << text.out;
}

// An injection is made in every frame: each frame's lighting.tiled is an origin (its inputs in
// frame 1 are finite again: lighting.composite's limit keeps the NaN out of every history).
// `frame 1` and `--this-frame` search that frame alone.
TEST(NanOrigin, EveryFrameIsSearchedOrTheCurrentOneAlone) {
  const fs::path path = shared_capture("nan-two-frames", kTwoFrames);
  const json all = inspect_json(path, "nan");
  EXPECT_EQ(all.at("frames"), json::array({0, 1}));
  ASSERT_EQ(all.at("origins").size(), 2u) << all;
  for (int frame : {0, 1}) {
    const json& origin = all.at("origins")[frame];
    EXPECT_EQ(origin.at("frame"), frame);
    EXPECT_EQ(origin.at("pass"), "lighting.tiled");
    EXPECT_EQ(origin.at("resources").at(0).at("texels").at(0).at("pixel"), json::array({40, 20}));
  }

  const CliResult text = run_cli("inspect " + quote(path) + " -c 'nan'");
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("frames 0-1: 2 origin(s)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("then one was written by frame 1, lighting.tiled"), std::string::npos) << text.out;

  const Inspected current = inspect(path, "frame 1 --json; nan --this-frame --json");
  ASSERT_EQ(current.result.code, 0) << current.result.err;
  const json& second = current.objects.at(1);
  EXPECT_EQ(second.at("frames"), json::array({1}));
  ASSERT_EQ(second.at("origins").size(), 1u) << second;
  EXPECT_EQ(second.at("origin").at("frame"), 1);
  EXPECT_EQ(second.at("origin").at("how"), "born");
}

TEST(NanOrigin, HalfResolutionOutputMapsThePixelToItsTexel) {
  const json j = inspect_json(shared_capture("nan-scaled", kScaled), "nan --limit 3");
  const json& origin = j.at("origin");
  EXPECT_EQ(origin.at("pass"), "bloom.level0");
  const json& output = origin.at("resources").at(0);
  EXPECT_EQ(output.at("resource"), "bloom.chain");
  EXPECT_EQ(output.at("count"), 1);
  const json& texel = output.at("texels").at(0);
  EXPECT_EQ(texel.at("texel"), json::array({50, 25}));
  // The first output pixel over texel 50 of 160 is 100 of 320 (and 50 of 180 for 25 of 90).
  EXPECT_EQ(texel.at("pixel"), json::array({100, 50}));
  const std::vector<json> inputs = texel.at("inputs");
  ASSERT_EQ(inputs.size(), 1u);
  EXPECT_EQ(inputs[0].at("resource"), "taa.resolved");
  EXPECT_EQ(inputs[0].at("texel"), json::array({100, 50}));
}

TEST(NanOrigin, ReplayWritesTheRecordedNanAgain) {
  const CliResult r = run_cli("replay --verify " + quote(shared_capture("nan-deferred", kInjected)));
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("replay matches the capture"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("NaN injected at texel (100, 50) of lighting.diffuse as recorded"), std::string::npos) << r.out;

  const CliResult scaled = run_cli("replay --verify --pass bloom.level0 --pass exposure --json " +
                                   quote(shared_capture("nan-scaled", kScaled)));
  EXPECT_EQ(scaled.code, 0) << scaled.out << scaled.err;
  const json report = json::parse(scaled.out);
  EXPECT_FALSE(report.at("different").get<bool>());
  for (const json& p : report.at("passes")) {
    EXPECT_EQ(p.at("notes").size(), 1u) << p;
    for (const json& o : p.at("outputs")) EXPECT_EQ(o.at("verdict"), "identical") << p;
  }
}

TEST(NanOrigin, BadInjectionsAreOneLineUsageErrors) {
  const fs::path dir = scratch("bad-inject");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"lighting.tiled100,50", "expected PASS:X,Y"},
      {"lighting.tiled:100", "expected PASS:X,Y"},
      {"lighting.tiled:-1,5", "expected PASS:X,Y"},
      {"no.such.pass:1,1", "no pass named 'no.such.pass'"},
      {"tonemap:1,1", "tonemap has no float colour output"},
      {"frame.constants:1,1", "frame.constants runs on the CPU"},
      {"lighting.tiled:320,0", "pixel (320, 0) is outside the 320x180 output"},
  };
  for (const auto& [flag, message] : cases) {
    const CliResult r =
        run_cli("render --city-block --size 320x180 --inject-nan '" + flag + "' -o " + quote(dir / "cap"));
    EXPECT_EQ(r.code, 2) << flag;
    EXPECT_NE(r.err.find("--inject-nan"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << flag << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "cap")) << flag;
  }
}

TEST(NanOrigin, AMalformedInjectionRecordIsRefusedNamingTheManifest) {
  const fs::path capture = scratch("hostile-inject") / "cap";
  fs::copy(shared_capture("nan-deferred", kInjected), capture, fs::copy_options::recursive);
  const json manifest = read_json(capture / "manifest.json");
  auto refused = [&](const std::string& field, const json& value, const std::string& message) {
    json edited = manifest;
    for (json& p : edited.at("frames").at(0).at("passes"))
      if (p.at("name") == "lighting.tiled") p.at("injected_nan")[field] = value;
    write_json(capture / "manifest.json", edited);
    const CliResult r = run_cli("passes " + quote(capture));
    EXPECT_EQ(r.code, 2) << field;
    EXPECT_NE(r.err.find("manifest.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  };
  refused("x", 320, "\"x\" must be an integer in 0..319");
  refused("y", "50", "\"y\" must be an integer in 0..179");
  refused("resource", "gbuffer.albedo", "'gbuffer.albedo' is not a float image output of the pass");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
