// depth.convert: device depth → depth.linear (R32_SFLOAT, metres along the view axis), the
// form every later stage samples. The half-resolution depth and stencil of frame.md arrive
// with the geometry stage. Never skipped (frame.md): every later stage reads it.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl depth_convert_pass() {
  return PassDecl("depth.convert", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.depth", Use::sampled)
      .write("depth.linear", Use::color_attachment, ImageDecl{VK_FORMAT_R32_SFLOAT, ResourceKind::linear_depth})
      .param("sky_depth", 1e6, 1.0, 3e38, "linear depth written where nothing was drawn (finite, so no Inf)")
      .compare("depth.linear", ComparisonContract::depth(0x1p-23,
                                                         "znear / depth is correctly rounded (0.5 ULP, "
                                                         "tests/unit/depth_convert_test.cpp): two devices "
                                                         "agree to 1 ULP"))
      .fullscreen("depth/convert.frag", [](const PassContext& ctx) {
        struct {
          float sky_depth;
        } constants{float(ctx.param("sky_depth"))};
        return constants;
      });
}

}  // namespace nightcap
