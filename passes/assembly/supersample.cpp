#include "passes/assembly/supersample.h"

#include <cstring>
#include <memory>

#include "passes/core/context.h"
#include "passes/core/format.h"

namespace nightcap {

Scene frozen(Scene scene) {
  for (Instance& instance : scene.instances) {
    instance.moving = false;
    instance.velocity = glm::vec3(0.0f);
  }
  return scene;
}

std::vector<double> supersampled_lit(GpuDevice& gpu, const Scene& scene, RenderSettings settings, uint32_t n,
                                     const RenderMonitor& monitor) {
  if (settings.path.speed() != 0 || !settings.path.cuts.empty())
    throw SceneError("supersampling averages renders of one still frame: the camera must hold still, without cuts");
  settings.frames = n * n;
  settings.first_recorded = 0;
  settings.last_recorded = UINT32_MAX;
  settings.params["taa"]["enabled"] = 0.0;
  settings.params["frame.constants"]["supersample"] = double(n);
  // Nothing after lighting.lit: neither taa nor post, nor the frame's other sinks.
  settings.sinks = {"lighting.lit"};
  settings.readback = {"lighting.lit"};
  settings.pass_timing = PassTiming::overlapped;  // no pass is timed: one submission per frame
  const size_t pixels = size_t(settings.width) * settings.height;
  std::vector<double> sum(pixels * 3, 0.0);
  Renderer renderer(gpu, scene, settings);
  for (uint32_t k = 0; k < n * n; ++k) {
    if (monitor.stop_requested()) throw RenderInterrupted("interrupted while supersampling: no capture written");
    monitor.progress("supersample " + std::to_string(k + 1) + "/" + std::to_string(n * n) + ": rendering");
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

std::vector<PassDecl> supersampled_frame_passes(const std::vector<double>& lit, uint32_t samples,
                                                FrameLighting lighting) {
  auto halves = std::make_shared<std::vector<uint8_t>>(lit.size() / 3 * 8);
  for (size_t p = 0; p < lit.size() / 3; ++p)
    for (size_t c = 0; c < 4; ++c) {
      const uint16_t h = float_to_half(c < 3 ? float(lit[p * 3 + c]) : 1.0f);
      std::memcpy(halves->data() + p * 8 + c * 2, &h, 2);
    }
  PassDecl supersampled =
      PassDecl(kSupersampledPass, PassType::cpu)
          .write("taa.resolved", Use::host, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
          .param_int("samples", samples, 1, 4096, "renders averaged per pixel (render --supersample N: N²)")
          .run([halves](PassContext& ctx) { ctx.output("taa.resolved") = *halves; });
  return frame_passes_resolved_by(std::move(supersampled), lighting);
}

}  // namespace nightcap
