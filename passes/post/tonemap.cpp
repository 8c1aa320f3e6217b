// tonemap: HDR lit colour (`lit`, as the frame's assembly names it) plus bloom → display (R8G8B8A8_SRGB): scaled by the
// manual exposure and, when the exposure pass ran, by its automatic one (exposure.value.x; 0 when it was skipped), then
// a filmic curve. The bloom is the mean of bloom.chain's levels, each upsampled bilinearly (in the shader, with exact
// weights) to the pixel centre. Where the graph knows the lit colour and the chain to be uniform (an empty scene's
// sky), a pipeline variant computes the one colour in the vertex shader and the fragments copy it: the same bits, since
// the interpolation gives equal texels back exactly. The grading LUT of frame.md feeds it once it exists.
#include "passes/core/context.h"
#include "passes/post/stage.h"
#include "passes/post/tonemap.glsl.h"

namespace nightcap {

PassDecl tonemap_pass(const std::string& lit) {
  return PassDecl("tonemap", PassType::graphics)
      .read(lit, Use::sampled)
      .as("lit")
      .read("exposure.value", Use::sampled)
      .read("bloom.chain", Use::sampled)
      .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_SRGB, kinds::colour})
      .param_float("exposure", 1.0, 0.0, 1e6,
                   "multiplies the HDR colour before the curve (with the automatic exposure, if any)")
      .param_float("bloom", 0.05, 0.0, 1e3, "weight of the bloom added to the lit colour")
      .compare("final.ldr", ComparisonContract::codes(1,
                                                      "within 0.67 of a code of the exact sRGB encoding "
                                                      "(tests/unit/tonemap_test.cpp); encoders may round the "
                                                      "other way"))
      .push_constants<TonemapConstants>()
      .shader("post/tonemap.vert")
      .shader("post/tonemap.frag")
      .run([lit](PassContext& ctx) {
        const TonemapConstants constants{float(ctx.param_float("exposure")), float(ctx.param_float("bloom"))};
        // Uniform inputs (an empty scene's sky): the variant that computes the colour once.
        const bool uniform = ctx.uniform(lit) && ctx.uniform("bloom.chain");
        record_fullscreen(ctx, {reinterpret_cast<const uint8_t*>(&constants), sizeof constants}, {uniform});
      });
}

}  // namespace nightcap
