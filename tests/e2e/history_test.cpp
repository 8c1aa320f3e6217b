// State across frames end to end: 8 frames of the city with a walking camera and a cut at
// frame 5. Every frame replays bit-identically from its own record; frame k's recorded history
// of exposure.value is frame k−1's recorded output (and the initial value, 0, at frames 0 and
// 5); the adapted exposure matches a CPU computation over the recorded frames; a capture that
// records only frames 3..5 holds the same frames as the full one; the camera moves as --motion
// says.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "captures/capture.h"
#include "passes/core/format.h"
#include "passes/frame/scene_resources.h"
#include "tests/e2e/cli.h"
#include "tests/reference/exposure_reference.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kWalk = "--city-block --size 160x90 --frames 8 --cut-at 5";

const PassRecord& find(const FrameRecord& frame, const std::string& pass) {
  for (const PassRecord& p : frame.passes)
    if (p.name == pass) return p;
  throw std::runtime_error("frame " + std::to_string(frame.index) + " has no pass " + pass);
}

const ResourceRecord& find(const std::vector<ResourceRecord>& list, const std::string& resource) {
  for (const ResourceRecord& r : list)
    if (r.resource == resource) return r;
  throw std::runtime_error("no resource " + resource);
}

std::vector<float> floats(const std::vector<uint8_t>& bytes) {
  std::vector<float> values(bytes.size() / 4);
  std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

TEST(History, EveryFrameReplaysFromItsOwnRecord) {
  const fs::path capture = shared_capture("walk-8", kWalk);
  for (int frame = 0; frame < 8; ++frame) {
    const CliResult r = run_cli("replay --verify --json --frame " + std::to_string(frame) + " " + quote(capture));
    EXPECT_EQ(r.code, 0) << "frame " << frame << ": " << r.out << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    EXPECT_FALSE(report.at("different").get<bool>()) << "frame " << frame;
    bool exposure_replayed = false;
    for (const auto& p : report.at("passes")) {
      exposure_replayed |= p.at("name") == "exposure" && p.at("replayed").get<bool>();
      for (const auto& o : p.value("outputs", nlohmann::json::array()))
        EXPECT_EQ(o.at("verdict"), "identical") << "frame " << frame << " " << o.at("resource");
    }
    EXPECT_TRUE(exposure_replayed) << "frame " << frame;
  }
}

TEST(History, EachFrameReadsThePreviousFramesOutputExceptAfterACut) {
  const Capture capture = Capture::open(shared_capture("walk-8", kWalk));
  ASSERT_EQ(capture.manifest().frames.size(), 8u);
  for (uint32_t k = 0; k < 8; ++k) {
    const FrameRecord& frame = capture.frame(k);
    EXPECT_DOUBLE_EQ(frame.time, k * kFrameSeconds);
    EXPECT_EQ(frame.camera_cut, k == 5);
    const ResourceRecord& history = find(find(frame, "exposure").inputs, "exposure.value@previous");
    if (k == 0 || k == 5) {
      EXPECT_EQ(frame.history_reset.at("exposure.value"), k == 0 ? "no earlier frame" : "camera cut");
      for (float v : floats(capture.load(history))) EXPECT_EQ(v, 0.0f) << "frame " << k << ": the initial value";
    } else {
      EXPECT_TRUE(frame.history_reset.empty()) << "frame " << k;
      const ResourceRecord& before = find(find(capture.frame(k - 1), "exposure").outputs, "exposure.value");
      EXPECT_EQ(history.hash, before.hash) << "frame " << k << " read something else than frame " << k - 1 << " wrote";
    }
  }
}

TEST(History, TheAdaptedExposureMatchesACpuComputationOverTheRecordedFrames) {
  const Capture capture = Capture::open(shared_capture("walk-8", kWalk));
  double adapted = 0;
  for (uint32_t k = 0; k < 8; ++k) {
    const PassRecord& exposure = find(capture.frame(k), "exposure");
    const double log2_min = exposure.params.at("log2_min"), log2_max = exposure.params.at("log2_max");
    const double tau = exposure.params.at("adapt_seconds");
    // The histogram of the recorded resolved image, in double precision.
    const std::vector<uint8_t> lit = capture.load(find(exposure.inputs, "taa.resolved"));
    std::vector<std::array<double, 3>> rgb;
    for (size_t p = 0; p + 8 <= lit.size(); p += 8) {
      uint16_t h[3];
      std::memcpy(h, lit.data() + p, 6);
      rgb.push_back({half_to_float(h[0]), half_to_float(h[1]), half_to_float(h[2])});
    }
    const reference::ExposureHistogram reference = reference::exposure_histogram(rgb, log2_min, log2_max);
    std::vector<uint32_t> recorded(kExposureBins);
    const std::vector<uint8_t> histogram_bytes = capture.load(find(exposure.outputs, "exposure.histogram"));
    ASSERT_EQ(histogram_bytes.size(), recorded.size() * 4);
    std::memcpy(recorded.data(), histogram_bytes.data(), histogram_bytes.size());
    uint64_t l1 = 0;
    for (size_t i = 0; i < kExposureBins; ++i)
      l1 += uint64_t(std::llabs(int64_t(recorded[i]) - int64_t(reference.bins[i])));
    EXPECT_LE(l1, 2 * reference.near_edges) << "frame " << k;
    const double measured = reference.measured;
    const bool restarted = capture.frame(k).history_reset.count("exposure.value") != 0;
    adapted = restarted ? measured : reference::adapt_exposure(measured, adapted, kFrameSeconds, tau);
    const double mean = std::exp2(adapted);
    const double scale = reference::automatic_key(mean) / mean;
    const std::vector<float> value = floats(capture.load(find(exposure.outputs, "exposure.value")));
    const double width = (log2_max - log2_min) / kExposureBins;
    const double bound = 1e-5 * (k + 1) + double(reference.near_edges) * width / double(reference.counted);
    EXPECT_NEAR(value[2], measured, bound) << "frame " << k;
    EXPECT_NEAR(value[1], adapted, bound) << "frame " << k;
    EXPECT_NEAR(value[0], scale, scale * bound) << "frame " << k;
  }
}

TEST(History, RecordingSomeFramesCarriesHistoryThroughTheOthers) {
  const Capture full = Capture::open(shared_capture("walk-8", kWalk));
  const fs::path dir = scratch("partial");
  const CliResult r = run_cli(std::string("render ") + kWalk + " --record-frames 3..5 -o " + quote(dir / "cap"));
  ASSERT_EQ(r.code, 0) << r.err;
  const Capture partial = Capture::open(dir / "cap");
  ASSERT_EQ(partial.manifest().frames.size(), 3u);
  for (uint32_t k = 3; k <= 5; ++k) {
    const FrameRecord &a = full.frame(k), &b = partial.frame(k);
    ASSERT_EQ(a.passes.size(), b.passes.size());
    for (size_t p = 0; p < a.passes.size(); ++p) {
      ASSERT_EQ(a.passes[p].inputs.size(), b.passes[p].inputs.size());
      for (size_t i = 0; i < a.passes[p].inputs.size(); ++i)
        EXPECT_EQ(a.passes[p].inputs[i].hash, b.passes[p].inputs[i].hash)
            << "frame " << k << " " << a.passes[p].name << " input " << a.passes[p].inputs[i].resource;
      ASSERT_EQ(a.passes[p].outputs.size(), b.passes[p].outputs.size());
      for (size_t i = 0; i < a.passes[p].outputs.size(); ++i)
        EXPECT_EQ(a.passes[p].outputs[i].hash, b.passes[p].outputs[i].hash)
            << "frame " << k << " " << a.passes[p].name << " output " << a.passes[p].outputs[i].resource;
    }
  }
  EXPECT_TRUE(partial.frame(3).history_reset.empty()) << "frame 3 adapts from frame 2, rendered but not recorded";
  EXPECT_NE(run_cli("replay --frame 2 " + quote(dir / "cap")).code, 0) << "frame 2 was not recorded";
}

TEST(History, TheCameraMovesAsMotionSays) {
  for (const auto& [motion, speed] :
       std::vector<std::pair<std::string, double>>{{"static", 0.0}, {"walk", 1.4}, {"drive", 14.0}}) {
    const fs::path dir = scratch("motion-" + motion);
    const CliResult r = run_cli("render --city-block --size 32x18 --frames 3 --cut-at 2 --motion " + motion + " -o " +
                                quote(dir / "cap"));
    ASSERT_EQ(r.code, 0) << r.err;
    const Capture capture = Capture::open(dir / "cap");
    auto position = [&](uint32_t k) {
      const auto& p = capture.frame(k).camera.position;
      return std::array<double, 3>{p[0], p[1], p[2]};
    };
    const auto p0 = position(0), p1 = position(1);
    const double moved = std::hypot(p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]);
    EXPECT_NEAR(moved, speed * kFrameSeconds, 1e-9) << motion;
    // The cut turns the view a quarter turn about the vertical: the horizontal part of the
    // view axis (row 2 of the column-major view matrix) turns by 90°.
    const auto& v1 = capture.frame(1).camera.view;
    const auto& v2 = capture.frame(2).camera.view;
    EXPECT_NEAR(v1[2] * v2[2] + v1[10] * v2[10], 0.0, 1e-9) << motion << ": the cut's heading is perpendicular";
    EXPECT_NEAR(v1[6], v2[6], 1e-9) << motion << ": the cut keeps the pitch";
    EXPECT_EQ(capture.manifest().settings.at("resolved").at("motion"), motion);
  }
}

TEST(History, BadFrameFlagsAreRefusedByName) {
  const fs::path dir = scratch("bad-flags");
  auto refused = [&](const std::string& flags, const std::string& message) {
    const CliResult r = run_cli("render --city-block --size 32x18 --frames 4 " + flags + " -o " + quote(dir / "cap"));
    EXPECT_EQ(r.code, 2) << flags;
    EXPECT_NE(r.err.find(message), std::string::npos) << flags << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir / "cap")) << flags;
  };
  refused("--cut-at 0", "--cut-at 0");
  refused("--cut-at 4", "--cut-at 4");
  refused("--record-frames 2..4", "--record-frames '2..4'");
  refused("--record-frames 3..1", "--record-frames '3..1'");
  refused("--record-frames x", "--record-frames 'x'");
  refused("--motion fly", "--motion 'fly'");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
