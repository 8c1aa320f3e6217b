// What taa is measured against (tests/unit/taa_test.cpp, the taa benchmark): the same still
// frame supersampled by the renderer itself, without TAA (passes/assembly/supersample.h), and the
// numbers that compare a resolved frame with it.
#pragma once

#include <cmath>
#include <vector>

#include "compare/flip.h"
#include "passes/assembly/renderer.h"
#include "passes/assembly/supersample.h"
#include "passes/core/format.h"

namespace nightcap::test {

// `settings` for `frames` frames of a still camera with exposure measured afresh each frame, so
// that a frame's exposure depends on its own image alone.
inline RenderSettings still_settings(RenderSettings settings, uint32_t frames) {
  settings.frames = frames;
  settings.path.motion = CameraPath::Motion::still;
  settings.params["exposure"]["adapt_seconds"] = 0.0;
  return settings;
}

// final.ldr of frame `frame` of a still camera with `resolved` (RGB per pixel, rounded to halves)
// in place of taa.resolved: the frame's post (bloom, exposure, tonemap) on that colour.
inline std::vector<uint8_t> final_of_resolved(GpuDevice& gpu, const Scene& scene, RenderSettings settings,
                                              uint32_t frame, const std::vector<double>& resolved) {
  Renderer renderer(gpu, scene, still_settings(settings, frame + 1), supersampled_frame_passes(resolved, 256),
                    builtin_shaders());
  return *renderer.render_frame(frame, false).execution.final_version("final.ldr")->bytes;
}

// PSNR of the RGB codes of two RGBA8 images, peak 255 (infinite when they are equal).
inline double psnr_rgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double squares = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (i % 4 != 3) squares += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  const double mse = squares / (double(a.size()) / 4 * 3);
  return mse == 0 ? INFINITY : 10.0 * std::log10(255.0 * 255.0 / mse);
}

// The mean LDR-FLIP error between two R8G8B8A8_SRGB images of width × height.
inline double flip_mean_srgb8(const std::vector<uint8_t>& reference, const std::vector<uint8_t>& test, uint32_t width,
                              uint32_t height) {
  auto linear = [](const std::vector<uint8_t>& codes) {
    std::vector<float> out(codes.size() / 4 * 3);
    for (size_t p = 0; p < out.size() / 3; ++p)
      for (size_t c = 0; c < 3; ++c) out[p * 3 + c] = srgb_to_linear(codes[p * 4 + c] / 255.0f);
    return out;
  };
  const std::vector<float> r = linear(reference), t = linear(test);
  return flip_ldr(FlipImage{width, height, 3, r}, FlipImage{width, height, 3, t}).mean;
}

}  // namespace nightcap::test
