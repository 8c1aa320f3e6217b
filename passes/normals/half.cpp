// normals.half: the half-resolution packed normal (normals.half, R8G8B8A8_UNORM best-fit normal
// and roughness) and motion (motion.half, R16G16_SFLOAT) that the half-resolution screen-space
// passes read beside depth.half and stencil.half (frame.md's ao.gtao). Each half texel copies
// the full texel depth.convert took its depth from, the footprint's nearest to the camera
// (depth/half_footprint.glsl): a selection, so every output is exactly an input value, and the
// four outputs describe one surface. An average would invent normals across silhouettes and
// blend the motion of a car with the street's.
#include "passes/core/context.h"
#include "passes/gbuffer/kinds.h"
#include "passes/normals/half.glsl.h"
#include "passes/normals/kinds.h"
#include "passes/normals/stage.h"

namespace nightcap {

PassDecl normals_half_pass() {
  ImageDecl normals{VK_FORMAT_R8G8B8A8_UNORM, kinds::packed_normal};
  normals.size.mode = SizeRule::Mode::output_half;
  normals.clear.color = {{128.0f / 255.0f, 128.0f / 255.0f, 128.0f / 255.0f, 0.0f}};  // normals.packed's
  ImageDecl motion{VK_FORMAT_R16G16_SFLOAT, kinds::motion};
  motion.size.mode = SizeRule::Mode::output_half;
  return PassDecl("normals.half", PassType::compute)
      .read("scene.depth", Use::sampled)
      .aspects("scene.depth", {ViewAspect::depth})
      .read("normals.packed", Use::sampled)
      .read("gbuffer.motion", Use::sampled)
      .write("normals.half", Use::storage_write, normals)
      .write("motion.half", Use::storage_write, motion)
      // Nothing drawn: every input holds its clear value, and so would every copy.
      .skip_when_cleared({"scene.depth", "normals.packed", "gbuffer.motion"})
      .shader("normals/half.comp")
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        const ImageExtent half = ctx.desc("normals.half").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kNormalsHalfGroupSide),
                      group_count(half.height, kNormalsHalfGroupSide), 1);
      });
}

}  // namespace nightcap
