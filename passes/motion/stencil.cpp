// motion.stencil: motion.mask (R8_UINT, full resolution), 1 on and around the pixels whose
// history TAA must distrust: those tagged moving (their history lies elsewhere on screen), and
// hair and foliage (thin, sub-pixel detail whose history flickers even when it stays still).
// The mask is dilated by `radius` pixels in a square window, the shape of TAA's neighbourhood,
// so silhouettes, which move across pixels the tag does not cover yet, are masked too.
//
// It reads only the stencil: gbuffer.dynamic, the writer of every per-object motion vector, sets
// the moving flag wherever it writes (frame.md), so a test of gbuffer.motion against camera-only
// motion would find the same pixels through a float threshold. Skipped when nothing in the scene
// moves and the camera is still: TAA's history then lines up everywhere, and the mask keeps its
// clear value, 0; so it does when nothing was drawn (scene.depth cleared: no tag anywhere).
#include "passes/core/context.h"
#include "passes/motion/stage.h"
#include "passes/motion/stencil.glsl.h"

namespace nightcap {

PassDecl motion_stencil_pass() {
  return PassDecl("motion.stencil", PassType::compute)
      .read("scene.depth", Use::sampled)
      .aspects("scene.depth", {ViewAspect::stencil})
      .write("motion.mask", Use::storage_write, ImageDecl{VK_FORMAT_R8_UINT, kinds::mask})
      .param_int("radius", 2, 0, kMotionStencilMaxRadius,
                 "pixels of dilation around tagged pixels (a square window), at most the apron the shader's tile holds")
      .skip_when([](const SkipContext& frame) -> std::string {
        if (frame.features.count("moving_geometry") || frame.camera_moved) return "";
        return "nothing moves and the camera is still";
      })
      .skip_when_cleared({"scene.depth"})
      .shader("motion/stencil.comp")
      .push_constants<MotionStencilConstants>()
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(MotionStencilConstants{int32_t(ctx.param_int("radius"))});
        const ImageExtent full = ctx.desc("motion.mask").extent;
        vkCmdDispatch(ctx.cmd(), group_count(full.width, kMotionStencilTile),
                      group_count(full.height, kMotionStencilTile), 1);
      });
}

}  // namespace nightcap
