// A pass's time, its clock and its stage, and a frame's wall clock, survive the manifest; a
// manifest written before they were recorded reads as timed by the device's timestamps (or the
// host's, for a CPU pass), and a clock the reader does not know is refused.
#include <gtest/gtest.h>

#include "captures/capture.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

CaptureManifest two_passes() {
  CaptureManifest manifest;
  manifest.device = manifest.settings = manifest.scene = nlohmann::json::object();
  FrameRecord frame;
  frame.width = frame.height = 8;
  frame.wall_ms = 12.5;
  PassRecord gpu;
  gpu.name = "shadow.cascades";
  gpu.stage = "shadows";
  gpu.ran = true;
  gpu.gpu_ms = 0.25;
  gpu.time_ms = 4.5;
  gpu.clock = PassClock::host_alone;
  gpu.record_ms = 30.25;
  PassRecord cpu;
  cpu.name = "cull.main";
  cpu.stage = "setup";
  cpu.ran = true;
  cpu.cpu_ms = cpu.time_ms = 1.5;
  frame.passes = {cpu, gpu};
  manifest.frames.push_back(frame);
  return manifest;
}

TEST(ManifestPassTime, TimesClocksStagesAndTheWallClockRoundTrip) {
  const CaptureManifest read = manifest_from_json(to_json(two_passes()), "manifest.json");
  const FrameRecord& frame = read.frames.at(0);
  EXPECT_EQ(frame.wall_ms, 12.5);
  EXPECT_EQ(frame.passes[0].stage, "setup");
  EXPECT_EQ(frame.passes[0].clock, PassClock::host);
  EXPECT_EQ(frame.passes[0].time_ms, 1.5);
  EXPECT_EQ(frame.passes[1].stage, "shadows");
  EXPECT_EQ(frame.passes[1].clock, PassClock::host_alone);
  EXPECT_EQ(frame.passes[1].time_ms, 4.5);
  EXPECT_EQ(frame.passes[1].gpu_ms, 0.25);
  EXPECT_EQ(frame.passes[1].record_ms, 30.25);
}

TEST(ManifestPassTime, AnEarlierManifestReadsAsTimedByTheDevice) {
  nlohmann::json json = to_json(two_passes());
  json["frames"][0].erase("wall_ms");
  for (auto& pass : json["frames"][0]["passes"])
    for (const char* key : {"time_ms", "clock", "stage", "record_ms"}) pass.erase(key);
  const FrameRecord frame = manifest_from_json(json, "manifest.json").frames.at(0);
  EXPECT_FALSE(frame.wall_ms);
  EXPECT_EQ(frame.passes[0].clock, PassClock::host);
  EXPECT_EQ(frame.passes[0].time_ms, 1.5);
  EXPECT_EQ(frame.passes[1].clock, PassClock::device);
  EXPECT_EQ(frame.passes[1].time_ms, 0.25);
  EXPECT_EQ(frame.passes[1].stage, "");
  EXPECT_EQ(frame.passes[1].record_ms, 0.0);
}

TEST(ManifestPassTime, AnUnknownClockOrAHostileStageIsRefused) {
  nlohmann::json json = to_json(two_passes());
  json["frames"][0]["passes"][1]["clock"] = "sundial";
  try {
    manifest_from_json(json, "manifest.json");
    ADD_FAILURE() << "an unknown clock was accepted";
  } catch (const CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find("\"clock\" must be device, host-alone or host"), std::string::npos)
        << e.what();
  }
  json = to_json(two_passes());
  json["frames"][0]["passes"][1]["stage"] = "../x";
  EXPECT_THROW(manifest_from_json(json, "manifest.json"), CaptureError);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
