// depth.prepass: depth of the opaque occluders before the G-buffer, so the G-buffer pass
// shades each pixel about once. Reversed-Z: cleared to 0 (infinitely far), GREATER passes.
#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl depth_prepass_pass() {
  ImageDecl depth{VK_FORMAT_D32_SFLOAT_S8_UINT, ResourceKind::depth_stencil};
  depth.clear.depthStencil = {0.0f, 0};
  return PassDecl("depth.prepass", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.geometry", Use::storage_read)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("draws.depth.prepass", Use::storage_read)
      .as("draws")
      .write("scene.depth", Use::depth_attachment, depth)
      .raster(RasterState::per_draw(VK_CULL_MODE_BACK_BIT))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER, true))
      .needs("opaque_geometry")
      .shader("depth/prepass.vert")
      .run([](PassContext& ctx) {
        ctx.begin_rendering();
        ctx.bind_pipeline();
        ctx.push_declared();
        draw_scene(ctx, "draws.depth.prepass", [](uint32_t, const GpuMaterial&) {});
        ctx.end_rendering();
      });
}

}  // namespace nightcap
