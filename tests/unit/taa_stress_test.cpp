// taa under stress: a cut every frame, outputs of 1×1 and 7×5, a NaN in the lit colour every
// frame, a camera jumping 100 m a frame, and 600 frames of a still camera. Each renders into a
// capture whose taa replays from its record (its history included) bit for bit every frame and
// whose float outputs stay finite (those after the injected NaN: taa's and post's); the 600
// frames keep the convergence of the 32nd (taa_test.cpp) against the supersampled frame.
#include <cstdio>

#include "passes/assembly/renderer.h"
#include "tests/reference/taa_reference.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/scratch_folder.h"
#include "tests/unit/verified_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

Scene city_block() {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  return scene;
}

// Frame f's taa.history frame counts (its alpha), from a capture.
std::vector<float> history_frames(const Capture& capture, uint32_t f) {
  std::vector<float> frames;
  const std::vector<uint16_t> texels = recorded<uint16_t>(capture, f, "taa", "taa.history");
  for (size_t i = 3; i < texels.size(); i += 4) frames.push_back(half_to_float(texels[i]));
  return frames;
}

class TaaStress : public GpuTest {};

TEST_F(TaaStress, ACutEveryFrameStartsEveryHistoryAgain) {
  const Scene scene = city_block();
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.cuts = {1, 2, 3, 4, 5};
  ScratchFolder folder("taa-cuts");
  const Capture capture = render_verified(*gpu_, scene, settings, 6, {"taa"}, folder.path / "cap");
  for (uint32_t f = 0; f < 6; ++f)
    for (const float frames : history_frames(capture, f)) ASSERT_EQ(frames, 1.0f) << "frame " << f;
}

TEST_F(TaaStress, OutputsOfOneByOneAndSevenByFive) {
  const Scene scene = city_block();
  for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{7u, 5u}}) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    ScratchFolder folder("taa-tiny");
    const Capture capture = render_verified(*gpu_, scene, settings, 4, {"taa"}, folder.path / "cap");
    EXPECT_EQ(history_frames(capture, 3).size(), size_t(width) * height);
  }
}

TEST_F(TaaStress, ACameraJumpingAHundredMetresAFrame) {
  const Scene scene = build_map({1, 16.0, Shot::street});
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.speed_override = 100.0 / kFrameSeconds;
  ScratchFolder folder("taa-jump");
  render_verified(*gpu_, scene, settings, 4, {"taa"}, folder.path / "cap");
}

TEST_F(TaaStress, ANanInTheLitColourEveryFrameLeavesTheResolvedColourFinite) {
  const Scene scene = city_block();
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.frames = 4;
  settings.inject_nan = {parse_inject_nan("lighting.composite:80,45")};
  ScratchFolder folder("taa-nan");
  render_to_capture(*gpu_, scene, settings, folder.path / "cap", false);
  const Capture capture = Capture::open(folder.path / "cap");
  for (uint32_t f = 0; f < 4; ++f) {
    bool after_taa = false;
    for (const PassRecord& pass : capture.frame(f).passes) {
      after_taa = after_taa || pass.name == "taa";
      if (!after_taa) continue;
      for (const ResourceRecord& out : pass.outputs) {
        if (out.is_buffer || !is_float(*format_info(out.format))) continue;
        EXPECT_TRUE(all_finite(out, capture.load(out))) << "frame " << f << ": " << pass.name << " " << out.resource;
      }
    }
    ReplayOptions options;
    options.frame = f;
    options.passes = {"taa"};
    for (const PassReplay& pass : replay_capture(*gpu_, capture, options).passes)
      for (const OutputCheck& check : pass.outputs) EXPECT_EQ(check.verdict, Verdict::identical) << check.resource;
  }
}

// The history does not drift: a still camera's frame 599 is as close to the supersampled frame
// as its frame 31 (320×180, to keep 856 frames within a test's time).
TEST_F(TaaStress, SixHundredStillFramesKeepTheirConvergence) {
  const Scene scene = frozen(city_block());
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.pass_timing = PassTiming::overlapped;  // untimed: one submission per frame
  const std::vector<double> supersampled = supersampled_lit(*gpu_, scene, still_settings(settings, 1), 16);
  Renderer renderer(*gpu_, scene, still_settings(settings, 600));
  double at_31 = 0, at_599 = 0;
  for (uint32_t k = 0; k < 600; ++k) {
    const RenderedFrame frame = renderer.render_frame(k, false);
    if (k != 31 && k != 599) continue;
    const std::vector<uint8_t> reference = final_of_resolved(*gpu_, scene, settings, k, supersampled);
    (k == 31 ? at_31 : at_599) = psnr_rgb8(reference, *frame.execution.final_version("final.ldr")->bytes);
  }
  std::printf("city block, 320x180, still: %.2f dB at frame 31, %.2f dB at frame 599\n", at_31, at_599);
  EXPECT_GE(at_31, 40.0);
  EXPECT_GE(at_599, 40.0);
  EXPECT_GE(at_599, at_31 - 0.5) << "the history drifted";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
