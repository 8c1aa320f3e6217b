// decals.projected: box volumes projected onto the G-buffer [000]. Each visible box of
// draws.decals.projected (cull.main) is drawn as its 36 back-face vertices, with no depth test,
// so it covers every pixel whose surface could lie inside it, the camera inside the box
// included. The fragment shader reads scene.depth's depth and stencil aspects at its pixel,
// reconstructs the surface's camera-relative position with frame.constants'
// inverse_view_projection, moves it into the box's unit cube and discards it outside the cube,
// on sky (depth 0: nothing to project onto, and no division by it) and on pixels tagged moving
// (stencil flag 0x02, frame.md): decals stay on the static world. Inside, the decal's pattern
// is blended fixed-function, a·decal + (1 − a)·surface, into gbuffer.albedo rgb,
// gbuffer.material rgb (metalness, roughness, translucency toward 0) and gbuffer.normal rgb
// (toward the box's +z, with weight a × normal_weight; later passes normalise what they read),
// the write masks keeping RT0's object flags, RT1's hair flag and RT2's emissive. Boxes blend in
// scene order.
//
// Skipped when the scene has no projected decal, when none is visible (cull.main left
// draws.decals.projected empty), or when nothing was drawn (scene.depth cleared: every pixel is
// sky, which it never touches).
#include <cstring>

#include "passes/core/context.h"
#include "passes/decals/stage.h"
#include "passes/frame/gpu_types.h"

namespace nightcap {
PassDecl decals_projected_pass() {
  return PassDecl("decals.projected", PassType::graphics)
      .read("frame.views", Use::uniform_buffer)
      .read("draws.decals.projected", Use::storage_read)
      .read("scene.depth", Use::sampled)
      .aspects("scene.depth", {ViewAspect::depth, ViewAspect::stencil})
      .modify("gbuffer.albedo", Use::color_attachment)
      .modify("gbuffer.normal", Use::color_attachment)
      .modify("gbuffer.material", Use::color_attachment)
      // One blend state for the three: the device does not enable independentBlend.
      .blend("gbuffer.albedo", BlendState::over_rgb())
      .blend("gbuffer.normal", BlendState::over_rgb())
      .blend("gbuffer.material", BlendState::over_rgb())
      // Back faces only: one fragment per pixel and box, wherever the camera is.
      .raster(RasterState{VK_CULL_MODE_FRONT_BIT, VK_FRONT_FACE_COUNTER_CLOCKWISE, false, {}})
      .needs("projected_decals")
      .skip_when_cleared({"scene.depth"})
      .skip_when_cleared({"draws.decals.projected"})
      .shader("decals/projected.vert")
      .shader("decals/projected.frag")
      .run([](PassContext& ctx) {
        const uint32_t count = uint32_t(ctx.host("draws.decals.projected").size() / sizeof(GpuDecal));
        ctx.begin_rendering();
        ctx.bind_pipeline();
        ctx.push_declared();
        if (count > 0) vkCmdDraw(ctx.cmd(), 36, count, 0, 0);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
