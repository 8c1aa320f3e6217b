// shadow.local_static: the static casters' depth of each spot light's map [004 §3], in
// kLocalShadowSlices cache slots (a D32 2D array) kept across frames as history.
// shadow.local_plan says what each slot holds (LocalShadowPlan::slot_state): a slot whose light
// and view are the previous frame's is copied from history (a transfer copy, PassContext::copy_layer), whether its
// light has a map this frame or not; a refreshed one is cleared and its static casters drawn (the first part of its
// map's range of draws.shadow.local); an empty one stays cleared. shadow.local then lays each map's slot down and draws
// the moving casters over it. The depth test keeps the least depth whatever the order of draws, so the sum is the map
// drawn in one go, bit for bit. Skipped with no spot light in the scene.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_local_static_pass() {
  return PassDecl("shadow.local_static", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.local", Use::storage_read)
      .as("draws")
      .read("shadow.local_views", Use::uniform_buffer)
      .read_previous("shadow.local_static", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.local_plan", Use::host)
      .write("shadow.local_static", Use::depth_attachment, shadow_depth_array(kLocalShadowSlices))
      .param_int("resolution", kLocalShadowResolution, 64, 2048,
                 "texels per side of each slot and of each map (shadow.local is sized like it)")
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("spot_lights")
      .push_constants<CasterConstants>()
      .shader("shadow/local.vert")
      .run([](PassContext& ctx) {
        const auto plan = host_records<LocalShadowPlan>(ctx.host("shadow.local_plan")).at(0);
        if (plan.maps > kLocalShadowSlices)
          throw GraphError("shadow.local_static: shadow.local_plan records " + std::to_string(plan.maps) + " maps");
        for (uint32_t slot = 0; slot < kLocalShadowSlices; ++slot) {
          const auto state = LocalSlotState(plan.slot_state[slot]);
          if (state == LocalSlotState::reused || state == LocalSlotState::kept) {
            ctx.copy_layer(previous("shadow.local_static"), slot, "shadow.local_static", slot);
            continue;
          }
          ctx.begin_rendering({}, "shadow.local_static", 0, slot);
          if (state != LocalSlotState::empty) {
            for (uint32_t map = 0; map < plan.maps; ++map) {
              const uint32_t statics = plan.slice_draws[map] - plan.slice_moving_draws[map];
              if (plan.slice_slot[map] != slot || statics == 0) continue;
              bind_casters(ctx, slot);
              draw_casters(ctx, "draws.shadow.local", {plan.slice_first_draw[map], statics});
            }
          }
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
