// exposure (frame.md section 7): auto-exposure from a histogram (kExposureBins bins) of the lit
// image's log2 luminance, adapted toward the histogram's mean over frames (exponentially, with a time
// constant in seconds) from the previous frame's value, a history input. exposure.value
// (1×1 RGBA32F) holds x: the scale tonemap multiplies by, y: the adapted log2 luminance (the
// history the next frame adapts from), z: this frame's measured mean log2 luminance. Its
// initial value, 0, means "no history": the first frame after a cut exposes for what it
// measures. The key (the luminance the mean maps to) is a parameter, or by default follows the
// mean as Krawczyk, Myszkowski and Seidel (2005) propose, so night stays night. Skipped (fixed exposure:
// tonemap.exposure alone) with exposure.enabled=0, which leaves exposure.value 0.
//
// It reads `lit`, the colour the frame's assembly names (passes/assembly/registry.cpp).
#include "passes/core/context.h"
#include "passes/post/exposure.glsl.h"
#include "passes/post/stage.h"

namespace nightcap {
PassDecl exposure_pass(const std::string& lit) {
  ImageDecl value{VK_FORMAT_R32G32B32A32_SFLOAT, kinds::hdr_colour};
  value.size = {SizeRule::Mode::absolute, 1, 1, {}};
  return PassDecl("exposure", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read(lit, Use::sampled)
      .as("lit")
      .read_previous("exposure.value", Use::sampled)
      .write("exposure.histogram", Use::storage_write, BufferDecl{kinds::buffer, kExposureBins * 4})
      .write("exposure.value", Use::storage_write, value)
      .can_disable("fixed exposure")
      .param_float("adapt_seconds", 1.0, 0.0, 60.0,
                   "time constant of the adaptation toward the measured exposure; 0: instant")
      .param_float("key", 0.0, 0.0, 100.0,
                   "the luminance the adapted mean is exposed to; 0: 1.03 - 2 / (2 + log10(mean + 1)) (Krawczyk et al. "
                   "2005), which keeps night scenes dark")
      .param_float("log2_min", -12.0, -64.0, 64.0, "lowest log2 luminance the histogram tells apart")
      .param_float("log2_max", 12.0, -64.0, 64.0, "highest log2 luminance the histogram tells apart")
      .push_constants<ExposureConstants>()
      .shader("post/exposure.comp")
      .run([lit](PassContext& ctx) {
        const ImageExtent extent = ctx.desc(lit).extent;
        // A uniform lit image (the sky of an empty scene) is counted from one texel: the same
        // integer counts, so the same bits after them.
        const bool uniform = ctx.uniform(lit);
        ExposureConstants constants{0,
                                    float(ctx.param_float("log2_min")),
                                    float(ctx.param_float("log2_max")),
                                    float(ctx.param_float("key")),
                                    float(ctx.param_float("adapt_seconds")),
                                    uniform ? extent.width * extent.height : 0u};
        if (!(constants.log2_max > constants.log2_min)) throw GraphError("exposure: log2_max must be above log2_min");
        ctx.bind_pipeline();
        ctx.push_declared();
        for (uint32_t phase = 0; phase < 3; ++phase) {
          constants.phase = phase;
          ctx.push_constants(constants);
          if (phase == 1 && !uniform)
            vkCmdDispatch(ctx.cmd(), group_count(extent.width, kExposureGroupSide),
                          group_count(extent.height, kExposureGroupSide), 1);
          else
            vkCmdDispatch(ctx.cmd(), 1, 1, 1);
          if (phase < 2) ctx.storage_barrier();
        }
      });
}

}  // namespace nightcap
