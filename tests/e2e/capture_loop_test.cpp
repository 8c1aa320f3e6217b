// The capture loop end to end on lavapipe with validation: render → passes → replay → diff.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <set>

#include "captures/capture.h"
#include "passes/depth/kinds.h"
#include "tests/e2e/cli.h"
#include "tests/reference/depth_half_reference.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kCity = "--city-block --size 320x180 --frames 2";
// Every pass of the frame, CPU passes included, one to a line.
// clang-format off
const std::vector<std::string> kFramePasses = {"cull.main",
                                               "frame.constants",
                                               "shadow.distant_plan",
                                               "shadow.distant",
                                               "shadow.cull",
                                               "shadow.cascades_static",
                                               "shadow.cascades",
                                               "shadow.local_plan",
                                               "shadow.local_static",
                                               "shadow.local",
                                               "shadow.local_moments",
                                               "shadow.topdown_plan",
                                               "shadow.topdown",
                                               "probes.plan",
                                               "probes.cull",
                                               "probes.gbuffer",
                                               "depth.prepass",
                                               "gbuffer.opaque",
                                               "depth.convert",
                                               "motion.stencil",
                                               "normals.bfn_lut",
                                               "normals.pack",
                                               "normals.half",
                                               "depth.pyramid",
                                               "ao.gtao",
                                               "ao.filter",
                                               "ao.temporal",
                                               "lights.cluster",
                                               "shadow.sun_resolve",
                                               "sky.atmosphere",
                                               "sky.transmittance",
                                               "sky.multiscattering",
                                               "sky.view",
                                               "sky.aerial_perspective",
                                               "sky.cubemap",
                                               "sky.irradiance",
                                               "sky.specular",
                                               "lighting.dfg",
                                               "probes.light",
                                               "probes.keep",
                                               "probes.convert",
                                               "probes.irradiance",
                                               "gi.plan",
                                               "gi.volume",
                                               "lighting.ltc_table",
                                               "lighting.tiled",
                                               "lighting.composite",
                                               "taa",
                                               "bloom.level0",
                                               "bloom.level1",
                                               "bloom.level2",
                                               "bloom.level3",
                                               "bloom.level4",
                                               "bloom.level5",
                                               "exposure",
                                               "tonemap"};
// clang-format on

// The passes that run in frame `frame` of kCity: the city has no moving geometry and the camera
// walks from frame 1 on, so motion.stencil is skipped in frame 0 only; its one reflection probe
// is captured in frame 0 and stays valid, so frame 1 captures nothing (and the GI volume, walking
// less than a cell, gathers nothing: it still runs, to carry the volume over).
std::vector<std::string> passes_that_run(int frame) {
  std::vector<std::string> passes = kFramePasses;
  if (frame == 0) std::erase(passes, "motion.stencil");
  if (frame > 0)
    for (const char* capture : {"probes.gbuffer", "probes.light", "probes.convert", "probes.irradiance"})
      std::erase(passes, capture);
  return passes;
}

// The passes a replay of frame `frame` of kCity runs: those that ran, and probes.convert and
// probes.irradiance when they skipped for want of captures: they only modify the probe array and
// irradiance, so their capture records their inputs and the replay checks they left them as they
// were.
std::vector<std::string> passes_that_replay(int frame) {
  std::vector<std::string> passes = passes_that_run(frame);
  if (frame > 0)
    passes.insert(std::find(passes.begin(), passes.end(), "gi.plan"), {"probes.convert", "probes.irradiance"});
  return passes;
}

nlohmann::json passes_json(const fs::path& capture) {
  const CliResult r = run_cli("passes --json " + quote(capture));
  EXPECT_EQ(r.code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

const nlohmann::json& find_pass(const nlohmann::json& frame, const std::string& name) {
  for (const auto& p : frame.at("passes"))
    if (p.at("name") == name) return p;
  throw std::runtime_error("no pass " + name);
}

TEST(CaptureLoop, RenderWritesACompleteCapture) {
  const fs::path dir = scratch("out");
  const CliResult r = run_cli(std::string("render ") + kCity + " -o " + quote(dir / "cap"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find((dir / "cap").string()), std::string::npos) << "render does not say where the capture is";
  const nlohmann::json manifest = read_json(dir / "cap" / "manifest.json");
  EXPECT_EQ(manifest.at("format"), "nightcap-capture");
  EXPECT_TRUE(manifest.at("version").is_number_integer());
  EXPECT_TRUE(fs::exists(dir / "cap" / "final.png"));
  EXPECT_EQ(manifest.at("frames").size(), 2u);
  EXPECT_NE(manifest.at("device").at("name").get<std::string>().find("llvmpipe"), std::string::npos);
  // Nothing but the capture is left beside it (the temporary sibling was renamed).
  std::vector<std::string> entries;
  for (const auto& entry : fs::directory_iterator(dir)) entries.push_back(entry.path().filename().string());
  EXPECT_EQ(entries, std::vector<std::string>{"cap"});
}

// With no scene, `render` renders the 16 km map from its street shot; --city-block the one
// block, which no map flag or glTF file goes with.
TEST(CaptureLoop, TheBuiltInSceneIsTheMapUnlessTheCityBlockIsAskedFor) {
  const fs::path dir = scratch("out");
  ASSERT_EQ(run_cli("render --size 64x36 -o " + quote(dir / "map")).code, 0);
  EXPECT_EQ(read_json(dir / "map" / "manifest.json").at("scene").at("source"),
            "built-in map (seed 1, 16 km, street shot)");
  ASSERT_EQ(run_cli("render --city-block --size 64x36 -o " + quote(dir / "block")).code, 0);
  EXPECT_EQ(read_json(dir / "block" / "manifest.json").at("scene").at("source"), "built-in city (seed 1)");
  const std::string box = quote(fs::path(NIGHTCAP_SHARED_DATA) / "gltf/BoxTextured/glTF/BoxTextured.gltf");
  for (const std::string& flags :
       std::vector<std::string>{"--city-block --shot street", "--city-block --map-size 2", "--city-block " + box}) {
    const CliResult r = run_cli("render " + flags + " -o " + quote(dir / "refused"));
    EXPECT_EQ(r.code, 2) << flags;
    EXPECT_NE(r.err.find("--city-block"), std::string::npos) << flags << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "refused"));
}

// Version 2: what tools and replay read instead of guessing.
TEST(CaptureLoop, ManifestRecordsOutputSizeSinksShaderSourcesAndPipelineState) {
  const fs::path capture = shared_capture("city", kCity);
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  EXPECT_EQ(manifest.at("version"), 5);
  size_t with_pipelines = 0;
  for (const auto& frame : manifest.at("frames")) {
    EXPECT_EQ(frame.at("output"), (nlohmann::json{{"width", 320}, {"height", 180}}));
    const auto sinks = frame.at("sinks").get<std::vector<std::string>>();
    EXPECT_NE(std::find(sinks.begin(), sinks.end(), "final.ldr"), sinks.end());
    for (const auto& p : frame.at("passes")) {
      if (p.at("status") != "ran" || p.at("gpu_ms").is_null()) continue;
      const std::string name = p.at("name");
      // A pass may run transfer commands only (shadow.cascades_static keeping every layer).
      if (p.at("pipelines").empty()) {
        EXPECT_TRUE(p.at("shaders").empty()) << name << " recorded shaders it did not bind";
        continue;
      }
      ++with_pipelines;
      std::set<std::string> recorded, bound;
      for (const auto& s : p.at("shaders")) {
        recorded.insert(s.at("path").get<std::string>());
        // The GLSL beside the SPIR-V is the source the pass was built from.
        std::ifstream in(std::string(NIGHTCAP_SOURCE) + "/passes/" + s.at("path").get<std::string>());
        const std::string source((std::istreambuf_iterator<char>(in)), {});
        std::ifstream blob(capture / s.at("source_blob").get<std::string>());
        EXPECT_EQ(std::string((std::istreambuf_iterator<char>(blob)), {}), source) << name << " " << s.at("path");
      }
      for (const auto& pipeline : p.at("pipelines"))
        for (const char* stage : {"vertex", "fragment", "shader"})
          if (pipeline.contains(stage) && !pipeline.at(stage).get<std::string>().empty())
            bound.insert(pipeline.at(stage).get<std::string>());
      EXPECT_EQ(bound, recorded) << name;
    }
  }
  EXPECT_GT(with_pipelines, 20u);
  // Every full-screen pass samples through a nearest clamp-to-edge sampler, and says so.
  const auto& tonemap = find_pass(manifest.at("frames")[0], "tonemap");
  ASSERT_EQ(tonemap.at("samplers").size(), 1u);
  EXPECT_EQ(tonemap.at("samplers")[0].at("mag_filter"), "nearest");
  EXPECT_EQ(tonemap.at("samplers")[0].at("wrap_u"), "clamp_to_edge");
  EXPECT_EQ(tonemap.at("pipelines")[0].at("color_formats"), nlohmann::json::array({"R8G8B8A8_SRGB"}));
  // The declared state: scene draws cull back faces per draw, the G-buffer writes the stencil.
  const auto& gbuffer = find_pass(manifest.at("frames")[0], "gbuffer.opaque").at("pipelines")[0];
  EXPECT_EQ(gbuffer.at("raster").at("cull_mode"), "back");
  EXPECT_EQ(gbuffer.at("raster").at("per_draw_faces"), true);
  EXPECT_EQ(gbuffer.at("stencil").at("write"), true);
  EXPECT_EQ(gbuffer.at("depth").at("compare"), "greater_or_equal");
  // Buffer outputs carry the schema their pass declared.
  for (const auto& out : find_pass(manifest.at("frames")[0], "cull.main").at("outputs")) {
    const std::string name = out.at("resource");
    if (name.rfind("draws.", 0) != 0) continue;
    ASSERT_TRUE(out.contains("schema")) << name;
    // Projected decals are boxes (GpuDecal); every other list is draws (GpuDraw).
    EXPECT_EQ(out.at("schema").at("stride"), name == "draws.decals.projected" ? 192 : 256) << name;
    EXPECT_EQ(out.at("schema").at("fields")[0], (nlohmann::json{{"name", "model"}, {"type", "mat4"}, {"offset", 0}}));
  }
  for (const auto& out : find_pass(manifest.at("frames")[0], "cull.main").at("outputs")) {
    if (out.at("resource") != "cull.stats") continue;
    EXPECT_EQ(out.at("schema").at("fields")[0],
              (nlohmann::json{{"name", "instances_tested"}, {"type", "u32"}, {"offset", 0}}));
  }
  for (const auto& out : find_pass(manifest.at("frames")[0], "frame.constants").at("outputs"))
    EXPECT_TRUE(out.contains("schema")) << out.at("resource");
}

TEST(CaptureLoop, ReplayTakesTheOutputSizeFromTheFrameNotTheCommandLine) {
  const fs::path copy = scratch("capture") / "no-settings";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  nlohmann::json manifest = read_json(copy / "manifest.json");
  manifest["settings"] = nlohmann::json::object();  // what the command line said is gone
  write_json(copy / "manifest.json", manifest);
  const CliResult r = run_cli("replay --verify --pass tonemap --pass depth.pyramid " + quote(copy));
  EXPECT_EQ(r.code, 0) << r.out << r.err;
}

TEST(CaptureLoop, TheSeedDeterminesTheCity) {
  const nlohmann::json a = read_json(shared_capture("city", kCity) / "manifest.json");
  const fs::path dir = scratch("seeds");
  ASSERT_EQ(run_cli(std::string("render ") + kCity + " -o " + quote(dir / "same")).code, 0);
  ASSERT_EQ(run_cli(std::string("render ") + kCity + " --scene-seed 2 -o " + quote(dir / "other")).code, 0);
  auto geometry_hash = [](const nlohmann::json& manifest) {
    for (const auto& p : manifest.at("frames")[0].at("passes"))
      for (const auto& in : p.at("inputs"))
        if (in.at("resource") == "scene.geometry") return in.at("hash").get<std::string>();
    return std::string();
  };
  const nlohmann::json same = read_json(dir / "same" / "manifest.json");
  EXPECT_EQ(geometry_hash(a), geometry_hash(same));
  EXPECT_NE(geometry_hash(a), geometry_hash(read_json(dir / "other" / "manifest.json")));
  // Same seed, same everything: the final images are the same blob.
  const auto final_blob = [](const nlohmann::json& manifest) {
    const auto& passes = manifest.at("frames")[1].at("passes");
    return passes.back().at("outputs")[0].at("hash").get<std::string>();
  };
  EXPECT_EQ(final_blob(a), final_blob(same));
}

nlohmann::json listing_settings(const fs::path& capture) { return read_json(capture / "manifest.json").at("settings"); }

// `--pass-times overlapped` keeps the device's timestamps as the passes' times.
TEST(CaptureLoop, OverlappedPassTimesAreTheDevicesTimestamps) {
  const fs::path dir = scratch("overlapped");
  const CliResult r = run_cli("render --city-block --size 64x36 --pass-times overlapped -o " + quote(dir / "cap"));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json manifest = read_json(dir / "cap" / "manifest.json");
  EXPECT_EQ(manifest.at("settings").at("resolved").at("pass_times"), "overlapped");
  for (const auto& p : manifest.at("frames")[0].at("passes")) {
    if (p.at("status") != "ran" || p.at("gpu_ms").is_null()) continue;
    EXPECT_EQ(p.at("clock"), "device") << p.at("name");
    EXPECT_EQ(p.at("time_ms"), p.at("gpu_ms")) << p.at("name");
  }
  const CliResult bad = run_cli("render --city-block --size 64x36 --pass-times fast -o " + quote(dir / "bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--pass-times 'fast'"), std::string::npos) << bad.err;
}

TEST(CaptureLoop, PassesJsonDescribesEveryPassAndResource) {
  const nlohmann::json listing = passes_json(shared_capture("city", kCity));
  ASSERT_EQ(listing.at("frames").size(), 2u);
  const nlohmann::json& frame = listing.at("frames")[0];
  EXPECT_EQ(frame.at("index"), 0);
  std::vector<std::string> ran;
  for (const auto& p : frame.at("passes")) {
    for (const char* key : {"name", "status", "gpu_ms", "params", "inputs", "outputs"})
      EXPECT_TRUE(p.contains(key)) << key;
    if (p.at("status") == "ran")
      ran.push_back(p.at("name"));
    else
      EXPECT_FALSE(p.at("reason").get<std::string>().empty());
    for (const char* side : {"inputs", "outputs"})
      for (const auto& r : p.at(side)) {
        for (const char* key : {"resource", "kind", "format", "width", "height", "mips", "layers", "hash", "blob"})
          EXPECT_TRUE(r.contains(key)) << p.at("name") << " " << key;
        EXPECT_TRUE(fs::exists(shared_capture("city", kCity) / r.at("blob").get<std::string>()));
      }
  }
  EXPECT_EQ(ran, passes_that_run(0));
  EXPECT_EQ(find_pass(frame, "motion.stencil").at("reason"), "nothing moves and the camera is still");
  // GPU passes carry a timestamp duration, CPU passes null; a GPU pass that ran took some time.
  EXPECT_TRUE(find_pass(frame, "cull.main").at("gpu_ms").is_null());
  ASSERT_TRUE(find_pass(frame, "gbuffer.opaque").at("gpu_ms").is_number());
  for (const auto& p : frame.at("passes")) {
    if (p.at("status") == "ran" && !p.at("gpu_ms").is_null()) {
      EXPECT_GT(p.at("gpu_ms").get<double>(), 0.0) << p.at("name");
    }
  }
  // On lavapipe (a CPU device) `render` times each GPU pass alone by the host's clock; a CPU
  // pass's time is its own run on the host. Each pass names its stage of the frame, and the
  // passes' times fit in the frame's wall clock.
  EXPECT_EQ(listing_settings(shared_capture("city", kCity)).at("resolved").at("pass_times"), "alone");
  double sum = 0.0;
  std::set<std::string> stages;
  for (const auto& p : frame.at("passes")) {
    stages.insert(p.at("stage").get<std::string>());
    if (p.at("status") != "ran") continue;
    EXPECT_EQ(p.at("clock"), p.at("gpu_ms").is_null() ? "host" : "host-alone") << p.at("name");
    if (p.at("gpu_ms").is_null()) {
      EXPECT_EQ(p.at("time_ms"), p.at("cpu_ms")) << p.at("name");
    }
    EXPECT_GT(p.at("time_ms").get<double>(), 0.0) << p.at("name");
    sum += p.at("time_ms").get<double>();
  }
  EXPECT_EQ(stages,
            (std::set<std::string>{"setup", "shadows", "probes", "geometry", "ao", "lighting", "gi", "taa", "post"}));
  EXPECT_EQ(find_pass(frame, "shadow.cascades").at("stage"), "shadows");
  EXPECT_EQ(find_pass(frame, "tonemap").at("stage"), "post");
  ASSERT_TRUE(frame.at("wall_ms").is_number());
  EXPECT_GE(frame.at("wall_ms").get<double>(), sum);
  // Exact formats of frame.md.
  std::map<std::string, std::string> formats;
  for (const auto& o : find_pass(frame, "gbuffer.opaque").at("outputs")) formats[o.at("resource")] = o.at("format");
  EXPECT_EQ(formats["gbuffer.albedo"], "A2B10G10R10_UNORM_PACK32");
  EXPECT_EQ(formats["gbuffer.normal"], "A2B10G10R10_UNORM_PACK32");
  EXPECT_EQ(formats["gbuffer.material"], "R8G8B8A8_UNORM");
  EXPECT_EQ(formats["gbuffer.motion"], "R16G16_SFLOAT");
  EXPECT_EQ(formats["scene.depth"], "D32_SFLOAT_S8_UINT");
  for (const auto& o : find_pass(frame, "lighting.tiled").at("outputs")) {
    if (o.at("kind") == "buffer") continue;
    EXPECT_EQ(o.at("format"), "R16G16B16A16_SFLOAT");
  }
  // Scene data the passes read is recorded, and stored once however many passes read it.
  std::set<std::string> blobs;
  for (const auto& p : frame.at("passes"))
    for (const auto& r : p.at("inputs"))
      if (r.at("resource") == "frame.constants") blobs.insert(r.at("blob").get<std::string>());
  EXPECT_EQ(blobs.size(), 1u);
}

const ResourceRecord& record_named(const std::vector<ResourceRecord>& records, const std::string& name) {
  for (const ResourceRecord& r : records)
    if (r.resource == name) return r;
  throw std::runtime_error("no resource " + name);
}

const PassRecord& pass_record(const FrameRecord& frame, const std::string& name) {
  for (const PassRecord& p : frame.passes)
    if (p.name == name) return p;
  throw std::runtime_error("no pass " + name);
}

// The city's recorded depth-stencil through the CPU reference of the half outputs: the stencil
// must match exactly, the depth be the nearest half of the recorded depth.linear at the chosen
// texel. motion.mask is recorded in both frames: frame 0 skips its pass and records the clear
// value, 0 everywhere.
TEST(CaptureLoop, HalfResolutionDepthAndStencilAndTheMotionMaskAreRecorded) {
  const Capture capture = Capture::open(shared_capture("city", kCity));
  const FrameRecord& frame = capture.frame(0);
  const PassRecord& convert = pass_record(frame, "depth.convert");
  const ResourceRecord& depth = record_named(convert.inputs, "scene.depth");
  const ResourceRecord& half_depth = record_named(convert.outputs, "depth.half");
  const ResourceRecord& half_stencil = record_named(convert.outputs, "stencil.half");
  EXPECT_EQ(half_depth.format, VK_FORMAT_R16_SFLOAT);
  EXPECT_EQ(half_stencil.format, VK_FORMAT_R8_UINT);
  EXPECT_EQ(half_stencil.kind, kinds::stencil);
  EXPECT_EQ(half_depth.extent.width, 160u);
  EXPECT_EQ(half_depth.extent.height, 90u);

  const uint32_t width = depth.extent.width, height = depth.extent.height;
  const size_t pixels = size_t(width) * height;
  const std::vector<uint8_t> depth_raw = capture.load(depth);
  std::vector<float> device(pixels);
  std::memcpy(device.data(), depth_raw.data(), pixels * 4);
  const std::vector<uint8_t> tags(depth_raw.begin() + pixels * 4, depth_raw.end());
  const reference::HalfDepthStencil expected =
      reference::half_depth_stencil(device, tags, width, height, frame.camera.znear, convert.params.at("sky_depth"));
  const std::vector<uint8_t> half_depth_raw = capture.load(half_depth), half_stencil_raw = capture.load(half_stencil);
  const std::vector<uint8_t> linear_raw = capture.load(record_named(convert.outputs, "depth.linear"));
  ASSERT_EQ(half_stencil_raw, expected.stencil);
  size_t sky = 0;
  for (size_t i = 0; i < expected.source.size(); ++i) {
    float linear;
    std::memcpy(&linear, linear_raw.data() + 4 * expected.source[i], 4);
    uint16_t bits;
    std::memcpy(&bits, half_depth_raw.data() + 2 * i, 2);
    ASSERT_EQ(bits, float_to_half(std::min(linear, 65504.0f))) << "half texel " << i;
    sky += half_to_float(bits) == 65504.0f;
  }
  EXPECT_GT(sky, 0u) << "the city frame shows sky";
  EXPECT_LT(sky, expected.source.size());

  const PassRecord& skipped = pass_record(frame, "motion.stencil");
  EXPECT_FALSE(skipped.ran);
  const std::vector<uint8_t> mask = capture.load(record_named(skipped.outputs, "motion.mask"));
  EXPECT_EQ(mask, std::vector<uint8_t>(pixels, 0));
  EXPECT_TRUE(pass_record(capture.frame(1), "motion.stencil").ran);
}

TEST(CaptureLoop, EveryPassThatRanReplaysBitIdentically) {
  const fs::path capture = shared_capture("city", kCity);
  const nlohmann::json listing = passes_json(capture);
  for (int frame : {0, 1}) {
    std::vector<std::string> ran;
    for (const auto& p : listing.at("frames")[frame].at("passes"))
      if (p.at("status") == "ran") ran.push_back(p.at("name"));
    EXPECT_EQ(ran, passes_that_run(frame)) << "frame " << frame;

    const CliResult r = run_cli("replay --verify --json --frame " + std::to_string(frame) + " " + quote(capture));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    std::vector<std::string> replayed;
    for (const auto& p : report.at("passes")) {
      if (!p.at("replayed")) continue;
      replayed.push_back(p.at("name"));
      EXPECT_FALSE(p.at("outputs").empty()) << p.at("name");
      for (const auto& o : p.at("outputs"))
        EXPECT_EQ(o.at("verdict"), "identical") << p.at("name") << " " << o.at("resource");
    }
    EXPECT_EQ(replayed, passes_that_replay(frame)) << "frame " << frame;
  }
}

TEST(CaptureLoop, ReplayWithAChangedParameterReportsTheDifference) {
  const CliResult r = run_cli("replay --verify --json --pass lighting.tiled --set lighting.tiled.intensity_scale=2 " +
                              quote(shared_capture("city", kCity)));
  EXPECT_EQ(r.code, 1) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  ASSERT_EQ(report.at("passes").size(), 1u);
  // The lighting changes; the tiles' classes and lists do not.
  for (const auto& o : report.at("passes")[0].at("outputs"))
    EXPECT_EQ(o.at("verdict"),
              o.at("resource").get<std::string>().rfind("lighting.tile_", 0) == 0 ? "identical" : "different")
        << o.at("resource");
}

TEST(CaptureLoop, ChainedReplayCarriesAChangeDownstream) {
  const CliResult r = run_cli("replay --verify --json --chain --set lighting.tiled.intensity_scale=2 " +
                              quote(shared_capture("city", kCity)));
  EXPECT_EQ(r.code, 1) << r.err;
  std::map<std::string, std::string> verdict;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  for (const auto& p : report.at("passes"))
    for (const auto& o : p.at("outputs"))
      verdict[o.at("resource").get<std::string>()] = o.at("verdict").get<std::string>();
  EXPECT_EQ(verdict["gbuffer.albedo"], "identical");
  EXPECT_EQ(verdict["lighting.diffuse"], "different");
  EXPECT_EQ(verdict["lighting.lit"], "different");
  EXPECT_EQ(verdict["final.ldr"], "different");
}

TEST(CaptureLoop, ReplayExecutesFromTheRecordedInputs) {
  // Point lighting.composite's diffuse input at the recorded specular blob: a valid blob of the
  // same format and size, so only a real re-execution can notice.
  const fs::path copy = scratch("capture") / "swapped";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  nlohmann::json manifest = read_json(copy / "manifest.json");
  nlohmann::json* diffuse = nullptr;
  nlohmann::json specular;
  for (auto& p : manifest.at("frames")[0].at("passes"))
    if (p.at("name") == "lighting.composite")
      for (auto& in : p.at("inputs")) {
        if (in.at("resource") == "lighting.diffuse") diffuse = &in;
        if (in.at("resource") == "lighting.specular") specular = in;
      }
  ASSERT_TRUE(diffuse && !specular.is_null());
  ASSERT_NE((*diffuse)["hash"], specular["hash"]);
  (*diffuse)["hash"] = specular["hash"];
  (*diffuse)["blob"] = specular["blob"];
  write_json(copy / "manifest.json", manifest);
  const CliResult r = run_cli("replay --verify --json --pass lighting.composite " + quote(copy));
  EXPECT_EQ(r.code, 1) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report.at("passes")[0].at("outputs")[0].at("verdict"), "different");
}

TEST(CaptureLoop, ReplayWithAnotherShaderReportsTheDifference) {
  const fs::path dir = scratch("shader");
  {
    std::ofstream shader(dir / "tonemap.frag");
    shader << "#version 460\nlayout(set = 0, binding = 0) uniform sampler2D lit_map;\n"
              "layout(location = 0) out vec4 out_ldr;\n"
              "void main() { out_ldr = vec4(texelFetch(lit_map, ivec2(gl_FragCoord.xy), 0).rgb, 1.0); }\n";
  }
  const CliResult r = run_cli("replay --verify --pass tonemap --shader tonemap=" + quote(dir / "tonemap.frag") + " " +
                              quote(shared_capture("city", kCity)));
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("different"), std::string::npos) << r.out;
}

TEST(CaptureLoop, DiffOfACaptureWithItselfIsClean) {
  const fs::path capture = shared_capture("city", kCity);
  const CliResult r = run_cli("diff --json " + quote(capture) + " " + quote(capture));
  EXPECT_EQ(r.code, 0) << r.err;
  const nlohmann::json diff = nlohmann::json::parse(r.out);
  EXPECT_TRUE(diff.at("first_divergence").is_null());
  EXPECT_FALSE(diff.at("beyond_tolerance"));
}

TEST(CaptureLoop, DiffNamesTonemapForAnExposureChange) {
  const fs::path a = shared_capture("city", kCity);
  const fs::path b = shared_capture("city-exposure", std::string(kCity) + " --set tonemap.exposure=2");
  const CliResult r = run_cli("diff --json " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1) << r.err;
  const nlohmann::json diff = nlohmann::json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence").at("pass"), "tonemap");
  const CliResult table = run_cli("diff " + quote(a) + " " + quote(b));
  EXPECT_NE(table.out.find("tonemap"), std::string::npos) << table.out;
  // final.ldr was held to the contract tonemap declared and recorded.
  for (const auto& p : diff.at("frames")[0].at("passes"))
    if (p.at("name") == "tonemap") {
      const auto& out = p.at("outputs")[0];
      EXPECT_EQ(out.at("held_to"), "within 1 code (recorded contract)");
      EXPECT_TRUE(out.at("beyond"));
      EXPECT_GT(out.at("contract").at("worst").get<double>(), 1.0);
    }
}

TEST(CaptureLoop, ToleranceOverridesTheContractsOfFloatOutputsOnly) {
  const fs::path a = shared_capture("city", kCity);
  const fs::path b = shared_capture("city-light", std::string(kCity) + " --set lighting.tiled.intensity_scale=1.5");
  const CliResult r = run_cli("diff --json --tolerance 1e9 " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1) << "final.ldr (UNORM codes) is still held to its contract: " << r.err;
  std::map<std::string, bool> beyond;
  const nlohmann::json diff = nlohmann::json::parse(r.out);
  for (const auto& p : diff.at("frames")[0].at("passes"))
    for (const auto& o : p.at("outputs"))
      if (o.contains("beyond")) beyond[o.at("resource").get<std::string>()] = o.at("beyond").get<bool>();
  EXPECT_FALSE(beyond.at("lighting.diffuse"));
  EXPECT_FALSE(beyond.at("lighting.lit"));
  EXPECT_TRUE(beyond.at("final.ldr"));
}

TEST(CaptureLoop, DiffNamesLightingAndMarksWhatInheritsIt) {
  const fs::path a = shared_capture("city", kCity);
  const fs::path b = shared_capture("city-light", std::string(kCity) + " --set lighting.tiled.intensity_scale=1.5");
  const CliResult r = run_cli("diff --json " + quote(a) + " " + quote(b));
  EXPECT_EQ(r.code, 1) << r.err;
  const nlohmann::json diff = nlohmann::json::parse(r.out);
  EXPECT_EQ(diff.at("first_divergence").at("pass"), "lighting.tiled");
  std::map<std::string, std::string> status;
  for (const auto& p : diff.at("frames")[0].at("passes")) status[p.at("name")] = p.at("status");
  EXPECT_EQ(status["lighting.tiled"], "origin");
  EXPECT_EQ(status["lighting.composite"], "inherited");
  EXPECT_EQ(status["tonemap"], "inherited");
  EXPECT_EQ(status["gbuffer.opaque"], "identical");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
