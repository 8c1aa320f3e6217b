// shadow.cascades (frame.md section 1): the sun's cascaded shadow map, one layer of a D32 2D
// array per cascade, each drawn from its own range of draws.shadow.cascades (no geometry-shader
// layer routing [001]) with the projections of shadow.cascade_data; shadow.cull chose both.
// D32 rather than D16: a cascade's light depth spans the whole scene toward the sun (up to
// 16 km of map at a low sun), where D16's 2⁻¹⁶ steps would be 0.25 m, coarser than the bias the
// resolve needs; D32 keeps millimetres. Depth is forward (0 at the light's near plane, LESS),
// casters are drawn from both sides (an open mesh still casts), and the bias is the resolve's,
// per receiver, not a raster bias here. Each layer starts as shadow.cascades_static's (the static
// casters, possibly kept from the previous frame) and this frame's moving casters are drawn over
// it. Skipped with no sun above the horizon.

#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_cascades_pass() {
  ImageDecl map{VK_FORMAT_D32_SFLOAT, kinds::light_depth};
  // Sized like the static layers, so the resolution is set on shadow.cull and shadow.cascades_static.
  map.size.mode = SizeRule::Mode::like;
  map.size.like = "shadow.cascades_static";
  map.layers = kShadowCascades;
  map.clear.depthStencil = {1.0f, 0};
  return PassDecl("shadow.cascades", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.cascades", Use::storage_read)
      .as("draws")
      .read("shadow.cascade_data", Use::uniform_buffer)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.cull_stats", Use::host)
      .read("shadow.cascades_static", Use::sampled)
      .write("shadow.cascades", Use::depth_attachment, map)
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("sun_above_horizon")
      .push_constants<CasterConstants>()
      .shader("shadow/cascades.vert")
      .run([](PassContext& ctx) {
        const auto stats = host_records<ShadowCullStats>(ctx.host("shadow.cull_stats")).at(0);
        for (uint32_t cascade = 0; cascade < kShadowCascades; ++cascade) {
          ctx.copy_layer("shadow.cascades_static", cascade, "shadow.cascades", cascade);
          if (stats.moving_draws[cascade] == 0) continue;
          ctx.begin_rendering({}, "shadow.cascades", 0, cascade);
          bind_casters(ctx, cascade);
          draw_casters(ctx, "draws.shadow.cascades",
                       {stats.first_draw[cascade] + stats.draws[cascade] - stats.moving_draws[cascade],
                        stats.moving_draws[cascade]});
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
