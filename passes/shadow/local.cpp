// shadow.local (frame.md section 1, [004 §3]): the depth of each spot light's shadow map, one
// layer of a D32 2D array per map that shadow.local_plan chose, each drawn from its own range
// of draws.shadow.local (no layer routing in a geometry shader [001]). D32, forward (0 at the
// near plane, LESS): a perspective depth crowds its precision near the light, and D16 would
// leave centimetre steps at a street light's range. Casters are drawn from both sides (an open
// mesh still casts); the bias is the lookup's. Each map starts as its cache slot of
// shadow.local_static (the static casters, possibly kept from earlier frames; a transfer copy)
// and this frame's moving casters are drawn over it. Layers without a map keep the clear (1: nothing).
// shadow.local_moments turns the depth into the moments lighting.tiled filters. Skipped with no
// spot light in the scene; a frame whose spot lights are all out of view draws nothing.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_local_pass() {
  // Sized like the cache slots, so the resolution is set on shadow.local_static alone.
  ImageDecl map = shadow_depth_array(kLocalShadowSlices);
  map.size.mode = SizeRule::Mode::like;
  map.size.like = "shadow.local_static";
  return PassDecl("shadow.local", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.local", Use::storage_read)
      .as("draws")
      .read("shadow.local_views", Use::uniform_buffer)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.local_plan", Use::host)
      .read("shadow.local_static", Use::sampled)
      .write("shadow.local", Use::depth_attachment, map)
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("spot_lights")
      .push_constants<CasterConstants>()
      .shader("shadow/local.vert")
      .run([](PassContext& ctx) {
        const auto plan = host_records<LocalShadowPlan>(ctx.host("shadow.local_plan")).at(0);
        for (uint32_t layer = 0; layer < kLocalShadowSlices; ++layer) {
          // A layer without a map is only cleared (1: nothing).
          if (layer >= plan.maps) {
            ctx.begin_rendering({}, "shadow.local", 0, layer);
            ctx.end_rendering();
            continue;
          }
          const uint32_t slot = plan.slice_slot[layer];
          if (slot >= kLocalShadowSlices)
            throw GraphError("shadow.local: shadow.local_plan puts map " + std::to_string(layer) + " in slot " +
                             std::to_string(slot));
          ctx.copy_layer("shadow.local_static", slot, "shadow.local", layer);
          if (plan.slice_moving_draws[layer] == 0) continue;
          ctx.begin_rendering({}, "shadow.local", 0, layer);
          bind_casters(ctx, slot);
          draw_casters(ctx, "draws.shadow.local",
                       {plan.slice_first_draw[layer] + plan.slice_draws[layer] - plan.slice_moving_draws[layer],
                        plan.slice_moving_draws[layer]});
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
