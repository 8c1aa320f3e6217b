// What taa is measured against (tests/unit/taa_test.cpp, the taa benchmark): the same still
// frame supersampled by the renderer itself, without TAA, and the numbers that compare a
// resolved frame with it.
#pragma once

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "compare/flip.h"
#include "passes/assembly/renderer.h"
#include "passes/core/context.h"
#include "passes/core/format.h"

namespace nightcap::test {

// The scene held still: cars and pedestrians stopped, drawn as the static geometry a still frame
// makes of them, so that every frame of a still camera renders the same picture.
inline Scene frozen(Scene scene) {
  for (Instance& instance : scene.instances) {
    instance.moving = false;
    instance.velocity = glm::vec3(0.0f);
  }
  return scene;
}

// `settings` for `frames` frames of a still camera with exposure measured afresh each frame, so
// that a frame's exposure depends on its own image alone.
inline RenderSettings still_settings(RenderSettings settings, uint32_t frames) {
  settings.frames = frames;
  settings.path.motion = CameraPath::Motion::still;
  settings.params["exposure"]["adapt_seconds"] = 0.0;
  return settings;
}

// The supersampled lit colour: the mean, in double, of lighting.lit's RGB over n² frames of a
// still camera, TAA off, frame k's projection offset to sample k of an n×n multi-jittered pattern
// over the pixel (frame.constants.supersample): a box filter of n² samples per pixel.
inline std::vector<double> supersampled_lit(GpuDevice& gpu, const Scene& scene, RenderSettings settings, uint32_t n) {
  settings = still_settings(settings, n * n);
  settings.params["taa"]["enabled"] = 0.0;
  settings.params["frame.constants"]["supersample"] = double(n);
  settings.readback = {"lighting.lit"};
  const size_t pixels = size_t(settings.width) * settings.height;
  std::vector<double> sum(pixels * 3, 0.0);
  Renderer renderer(gpu, scene, settings);
  for (uint32_t k = 0; k < n * n; ++k) {
    const RenderedFrame frame = renderer.render_frame(k, false);
    const std::vector<uint8_t>& lit = *frame.execution.final_version("lighting.lit")->bytes;
    for (size_t p = 0; p < pixels; ++p)
      for (size_t c = 0; c < 3; ++c) {
        uint16_t h;
        std::memcpy(&h, lit.data() + p * 8 + c * 2, 2);
        sum[p * 3 + c] += double(half_to_float(h));
      }
  }
  for (double& v : sum) v /= double(n) * n;
  return sum;
}

// final.ldr of frame `frame` of a still camera with `resolved` (RGB per pixel, rounded to halves)
// in place of taa.resolved: the frame's post (bloom, exposure, tonemap) on that colour.
inline std::vector<uint8_t> final_of_resolved(GpuDevice& gpu, const Scene& scene, RenderSettings settings,
                                              uint32_t frame, const std::vector<double>& resolved) {
  settings = still_settings(settings, frame + 1);
  auto bytes = std::make_shared<std::vector<uint8_t>>(resolved.size() / 3 * 8);
  for (size_t p = 0; p < resolved.size() / 3; ++p)
    for (size_t c = 0; c < 4; ++c) {
      const uint16_t h = float_to_half(c < 3 ? float(resolved[p * 3 + c]) : 1.0f);
      std::memcpy(bytes->data() + p * 8 + c * 2, &h, 2);
    }
  std::vector<PassDecl> passes = frame_passes();
  std::erase_if(passes, [](const PassDecl& pass) { return pass.name == "taa"; });
  passes.push_back(PassDecl("test.resolved", PassType::cpu)
                       .write("taa.resolved", Use::host, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
                       .run([bytes](PassContext& ctx) { ctx.output("taa.resolved") = *bytes; }));
  passes.back().stage = "taa";
  Renderer renderer(gpu, scene, settings, passes, builtin_shaders());
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
