// tonemap: HDR lit colour → display (R8G8B8A8_SRGB): scaled by the manual exposure and, when
// the exposure pass ran, by its automatic one (exposure.value.x; 0 when it was skipped), then a
// filmic curve. Bloom and the grading LUT of frame.md feed it once they exist.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl tonemap_pass() {
  return PassDecl("tonemap", PassType::graphics)
      .read("lighting.lit", Use::sampled)
      .read("exposure.value", Use::sampled)
      .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_SRGB, ResourceKind::colour})
      .param("exposure", 1.0, 0.0, 1e6,
             "multiplies the HDR colour before the curve (with the automatic exposure, if any)")
      .compare("final.ldr", ComparisonContract::codes(1,
                                                      "within 0.67 of a code of the exact sRGB encoding "
                                                      "(tests/unit/tonemap_test.cpp); encoders may round the "
                                                      "other way"))
      .fullscreen("post/tonemap.frag", [](const PassContext& ctx) {
        struct {
          float exposure;
        } constants{float(ctx.param("exposure"))};
        return constants;
      });
}

}  // namespace nightcap
