// taa and its jitter (passes/taa/taa.cpp, passes/frame/jitter.h) against references that do not
// use them:
// - convergence: 32 still frames of the city block and of the map's street shot, 640×360,
//   resolved by TAA, against the same still frame supersampled by the renderer itself (256
//   frames offset over a 16×16 multi-jittered pattern, TAA off, lighting.lit averaged in double,
//   then the frame's post): final.ldr within 40 dB PSNR (8-bit codes, peak 255); LDR-FLIP against
//   it and between the last two frames printed;
// - ghosting: a bright square moving 4 pixels a frame over a textured background leaves less
//   than 1/255 of its contrast 8 frames after it left a pixel, where plain 10% blending keeps
//   0.9⁸ = 43%;
// - non-finite light: a NaN and a +Inf in one frame's lit colour leave every resolved and history
//   texel finite for 100 frames, and bloom after them;
// - the jitter: Halton (2, 3) of period 32 centred on the pixel, frame 0 unjittered, recorded in
//   frame.views; motion vectors of a still camera stay zero under it;
// - off: with taa.enabled=0 every resource of the frame is bit for bit what a frame assembled
//   without taa computes.
#include <algorithm>
#include <cstdio>
#include <set>

#include "passes/frame/gpu_types.h"
#include "passes/frame/jitter.h"
#include "passes/post/stage.h"
#include "passes/taa/stage.h"
#include "tests/reference/taa_reference.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/scratch_folder.h"
#include "tests/unit/verified_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// The synthetic frames of the ghosting and NaN tests: lit colour, motion and mask of width × height.
struct SyntheticFrame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> lit;
  std::vector<glm::vec2> motion;  // uv units, current minus previous
  std::vector<uint8_t> mask;
  glm::vec3& at(uint32_t x, uint32_t y) { return lit[size_t(y) * width + x]; }
};

SyntheticFrame textured_background(uint32_t width, uint32_t height) {
  SyntheticFrame f{width, height, {}, {}, {}};
  f.lit.resize(size_t(width) * height);
  f.motion.assign(f.lit.size(), glm::vec2(0.0f));
  f.mask.assign(f.lit.size(), 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) f.at(x, y) = glm::vec3((x + y) % 2 ? 0.22f : 0.18f);
  return f;
}

std::vector<uint8_t> rgba16f(const std::vector<glm::vec3>& rgb, float alpha) {
  std::vector<uint8_t> bytes(rgb.size() * 8);
  for (size_t i = 0; i < rgb.size(); ++i) {
    const uint16_t h[4] = {float_to_half(rgb[i].r), float_to_half(rgb[i].g), float_to_half(rgb[i].b),
                           float_to_half(alpha)};
    std::memcpy(bytes.data() + i * 8, h, 8);
  }
  return bytes;
}

glm::vec4 texel16f(const std::vector<uint8_t>& bytes, size_t i) {
  glm::vec4 texel;
  decode_texel(*format_info(VK_FORMAT_R16G16B16A16_SFLOAT), 0, bytes, i, &texel[0]);
  return texel;
}

class Taa : public GpuTest {
 protected:
  // Runs taa on `frame` with `history` (empty: none, the cleared history of frame 0) and the mask
  // of the frame before (empty: none); the caller feeds outputs.at("taa.history") to the next frame.
  static IsolatedRun resolve(const SyntheticFrame& frame, const std::vector<uint8_t>& history,
                             const std::vector<uint8_t>& previous_mask = {}) {
    std::vector<uint8_t> motion(frame.motion.size() * 4);
    for (size_t i = 0; i < frame.motion.size(); ++i) {
      const uint16_t h[2] = {float_to_half(frame.motion[i].x), float_to_half(frame.motion[i].y)};
      std::memcpy(motion.data() + i * 4, h, 4);
    }
    const uint32_t w = frame.width, h = frame.height;
    const std::vector<uint8_t> no_history(size_t(w) * h * 8, 0);
    return run(
        taa_pass(),
        {{"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, w, h, rgba16f(frame.lit, 1.0f))},
         {previous("taa.history"),
          image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, w, h, history.empty() ? no_history : history)},
         {"gbuffer.motion", image(VK_FORMAT_R16G16_SFLOAT, kinds::hdr_colour, w, h, motion)},
         {"motion.mask", image(VK_FORMAT_R8_UINT, kinds::mask, w, h, frame.mask)},
         {previous("motion.mask"),
          image(VK_FORMAT_R8_UINT, kinds::mask, w, h,
                previous_mask.empty() ? std::vector<uint8_t>(size_t(w) * h, 0) : previous_mask)}},
        w, h);
  }
};

void expect_converges(GpuDevice& gpu, const char* name, const Scene& scene) {
  RenderSettings settings;
  settings.width = 640;
  settings.height = 360;
  const uint32_t frames = 32;
  const std::vector<uint8_t> supersampled = final_of_resolved(
      gpu, scene, settings, frames - 1, supersampled_lit(gpu, scene, still_settings(settings, 1), 16));
  Renderer renderer(gpu, scene, still_settings(settings, frames));
  std::vector<uint8_t> previous, resolved;
  for (uint32_t k = 0; k < frames; ++k) {
    previous = std::move(resolved);
    resolved = *renderer.render_frame(k, false).execution.final_version("final.ldr")->bytes;
  }
  const double psnr = psnr_rgb8(supersampled, resolved);
  std::printf(
      "%s, 640x360, %u still frames: %.2f dB PSNR against 256 samples; LDR-FLIP %.4f against them, %.4f "
      "between the last two frames\n",
      name, frames, psnr, flip_mean_srgb8(supersampled, resolved, 640, 360),
      flip_mean_srgb8(previous, resolved, 640, 360));
  EXPECT_GE(psnr, 40.0) << name;
}

TEST_F(Taa, StillFramesOfTheCityBlockConvergeToTheSupersampledFrame) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  expect_converges(*gpu_, "city block", frozen(std::move(scene)));
}

TEST_F(Taa, StillFramesOfTheMapStreetShotConvergeToTheSupersampledFrame) {
  expect_converges(*gpu_, "map street shot", frozen(build_map({1, 16.0, Shot::street})));
}

// A 2.0 square of 8×8 pixels moving 4 pixels a frame to the right over a background of 0.2 ± 0.02,
// tagged in motion.mask (dilated by 2 pixels, as motion.stencil's default) with its motion.
SyntheticFrame square_at(uint32_t left) {
  SyntheticFrame f = textured_background(96, 24);
  const uint32_t top = 8;
  for (uint32_t y = 0; y < f.height; ++y)
    for (uint32_t x = 0; x < f.width; ++x) {
      const bool inside = x >= left && x < left + 8 && y >= top && y < top + 8;
      const bool near = x + 2 >= left && x < left + 10 && y + 2 >= top && y < top + 10;
      if (inside) {
        f.at(x, y) = glm::vec3(2.0f);
        f.motion[size_t(y) * f.width + x] = glm::vec2(4.0f / f.width, 0.0f);
      }
      f.mask[size_t(y) * f.width + x] = near ? 1 : 0;
    }
  return f;
}

TEST_F(Taa, AMovingObjectLeavesLessThanOneCodeOfGhostAfterEightFrames) {
  // The square's frames, and the same frames without it: the ghost is what the square leaves in
  // the resolved colour beyond what the background alone resolves to. Frame 0 has no history:
  // the square's pixels hold it. It has left columns 4..11 by frame 2.
  const uint32_t last = 10;
  std::vector<uint8_t> history, background_history;
  std::vector<IsolatedRun> runs;
  IsolatedRun background;
  for (uint32_t k = 0; k <= last; ++k) {
    runs.push_back(
        resolve(square_at(4 + 4 * k), history, k > 0 ? square_at(4 + 4 * (k - 1)).mask : std::vector<uint8_t>{}));
    history = *runs.back().outputs.at("taa.history");
    background = resolve(textured_background(96, 24), background_history);
    background_history = *background.outputs.at("taa.history");
  }
  const std::vector<uint8_t>& resolved = *runs.back().outputs.at("taa.resolved");
  const std::vector<uint8_t>& alone = *background.outputs.at("taa.resolved");
  double worst = 0.0;
  for (uint32_t y = 8; y < 16; ++y)
    for (uint32_t x = 4; x < 12; ++x) {
      const size_t i = size_t(y) * 96 + x;
      worst = std::max(worst, double(glm::length(glm::vec3(texel16f(resolved, i) - texel16f(alone, i)))));
    }
  // 8 frames after the square left these pixels, what is left of its contrast (2.0 against 0.2).
  const double ghost = worst / 1.8;
  const double plain_blend = std::pow(0.9, double(last - 2));
  std::printf("ghost 8 frames after the square left: %.2e of its contrast (plain 10%% blending: %.3f)\n", ghost,
              plain_blend);
  EXPECT_LT(ghost, 1.0 / 255.0);
  EXPECT_NEAR(plain_blend, 0.43, 0.005);
  // On the square the mask keeps the history short; off it the history keeps growing.
  const std::vector<uint8_t>& kept = *runs.back().outputs.at("taa.history");
  const uint32_t square_left = 4 + 4 * last;
  EXPECT_LE(texel16f(kept, size_t(10) * 96 + square_left + 3).a, 2.0f);
  EXPECT_EQ(texel16f(kept, size_t(10) * 96 + 90).a, 11.0f) << "11 frames of a still background";
}

TEST_F(Taa, ANanAndAnInfinityInOneFrameLeaveEveryLaterFrameFinite) {
  std::vector<uint8_t> history;
  IsolatedRun last;
  for (uint32_t k = 0; k < 100; ++k) {
    SyntheticFrame frame = textured_background(32, 16);
    if (k == 0) {
      frame.at(5, 5) = glm::vec3(NAN, 1.0f, 1.0f);
      frame.at(20, 9) = glm::vec3(INFINITY);
    }
    last = resolve(frame, history);
    for (const char* output : {"taa.resolved", "taa.history"}) {
      const std::vector<uint8_t>& bytes = *last.outputs.at(output);
      for (size_t i = 0; i < bytes.size() / 8; ++i)
        for (int c = 0; c < 4; ++c)
          ASSERT_TRUE(std::isfinite(texel16f(bytes, i)[c])) << "frame " << k << ": " << output << " texel " << i;
    }
    if (k == 0) {
      const glm::vec4 bright = texel16f(*last.outputs.at("taa.resolved"), size_t(9) * 32 + 20);
      EXPECT_EQ(bright.r, 65504.0f) << "+Inf stays the brightest light a half holds";
    }
    history = *last.outputs.at("taa.history");
  }
  const IsolatedRun bloom = run(bloom_level_pass(0, "taa.resolved"),
                                {{"taa.resolved", image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, 32, 16,
                                                        *last.outputs.at("taa.resolved"))}},
                                32, 16);
  EXPECT_EQ(first_non_finite(bloom.execution), "");
}

TEST(TaaJitter, IsHaltonTwoThreeCentredOnThePixelWithFrameZeroUnjittered) {
  EXPECT_EQ(taa_jitter(0), glm::dvec2(0.0));
  std::set<std::pair<double, double>> points;
  glm::dvec2 mean(0.0);
  for (uint32_t k = 1; k <= kJitterPeriod; ++k) {
    const glm::dvec2 j = taa_jitter(k);
    EXPECT_EQ(taa_jitter(k + kJitterPeriod), j);
    EXPECT_TRUE(j.x > -0.5 && j.x < 0.5 && j.y > -0.5 && j.y < 0.5) << k;
    points.insert({j.x, j.y});
    mean += j / double(kJitterPeriod);
  }
  EXPECT_EQ(points.size(), kJitterPeriod);
  EXPECT_LT(glm::length(mean), 1e-12) << "a period's samples centre on the pixel";
  // Halton (2, 3) points 1 and 2 are (1/2, 1/3) and (1/4, 2/3): frames 1 and 2 differ by theirs.
  EXPECT_NEAR(taa_jitter(2).x - taa_jitter(1).x, -0.25, 1e-12);
  EXPECT_NEAR(taa_jitter(2).y - taa_jitter(1).y, 1.0 / 3.0, 1e-12);
}

TEST_F(Taa, TheJitterIsRecordedPerFrameAndMotionVectorsOfAStillCameraHoldNone) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  const Scene still = frozen(std::move(scene));
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.motion = CameraPath::Motion::still;
  settings.readback = {"frame.views", "gbuffer.motion"};
  Renderer renderer(*gpu_, still, settings);
  for (uint32_t k = 0; k < 4; ++k) {
    const RenderedFrame frame = renderer.render_frame(k, false);
    const GpuView view = host_records<GpuView>(*frame.execution.final_version("frame.views")->bytes).at(0);
    EXPECT_EQ(view.jitter.x, float(taa_jitter(k).x)) << k;
    EXPECT_EQ(view.jitter.y, float(taa_jitter(k).y)) << k;
    const std::vector<uint8_t>& motion = *frame.execution.final_version("gbuffer.motion")->bytes;
    float longest = 0.0f;
    for (size_t i = 0; i < motion.size() / 2; ++i) {
      uint16_t h;
      std::memcpy(&h, motion.data() + i * 2, 2);
      longest = std::max(longest, std::abs(half_to_float(h)));
    }
    EXPECT_LT(longest * 160.0f, 1e-3f) << "frame " << k << ": motion in pixels";
  }
  settings.params["taa"]["enabled"] = 0.0;
  Renderer off(*gpu_, still, settings);
  const RenderedFrame frame = off.render_frame(1, false);
  EXPECT_EQ(host_records<GpuView>(*frame.execution.final_version("frame.views")->bytes).at(0).jitter, glm::vec4(0.0f));
}

TEST_F(Taa, TurnedOffEveryResourceIsWhatAFrameWithoutTaaComputes) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.params["taa"]["enabled"] = 0.0;
  std::vector<PassDecl> without;
  add_scene_passes(without);
  add_lighting_passes(without, FrameLighting::tiled);
  add_post_passes(without, "lighting.lit");
  Renderer off(*gpu_, scene, settings);
  Renderer none(*gpu_, scene, settings, without, builtin_shaders());
  for (uint32_t k = 0; k < 3; ++k) {
    const RenderedFrame a = off.render_frame(k, true), b = none.render_frame(k, true);
    size_t compared = 0;
    for (const VersionData& version : b.execution.versions) {
      if (!version.bytes) continue;
      const VersionData* same = a.execution.final_version(version.resource);
      if (!same || b.execution.final_version(version.resource) != &version) continue;
      EXPECT_TRUE(*same->bytes == *version.bytes) << "frame " << k << ": " << version.resource;
      ++compared;
    }
    EXPECT_GT(compared, 50u);
    EXPECT_TRUE(*a.execution.final_version("taa.resolved")->bytes == *a.execution.final_version("lighting.lit")->bytes);
  }
}

TEST_F(Taa, ReplaysFromItsRecordWithItsHistoryEveryFrameThroughACut) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.cuts = {2};
  ScratchFolder folder("taa_replay");
  const Capture capture = render_verified(*gpu_, scene, settings, 4, {"taa"}, folder.path / "capture");
  // On the cut the history starts again from the frame itself.
  const auto history = recorded<uint16_t>(capture, 2, "taa", "taa.history");
  ASSERT_FALSE(history.empty());
  for (size_t i = 3; i < history.size(); i += 4) ASSERT_EQ(half_to_float(history[i]), 1.0f) << "texel " << i / 4;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
