// shadow.distant (frame.md section 1, [004 §2.1]): the sun's distant shadow, four levels of a
// D32 2D array, each 4× the side of the previous, the last covering the whole map; where they
// lie and what is redrawn this frame is shadow.distant_plan's (which says why). The levels are
// history: each layer starts from the previous frame's, moved by whole texels with the camera
// (a transfer copy, PassContext::copy_layer; newly covered texels at 1, no occluder), then each
// planned tile is cleared to 1 and its static casters drawn under its own scissor. A level with
// nothing redrawn is only carried over. shadow.sun_resolve reads level 0
// (and the coarser ones) as the occluder beyond the last cascade.
// D32, as shadow.cascades and for the same reason: a level's depth spans the whole static scene
// toward the sun. Skipped with no sun above the horizon, or by `enabled=0` (the resolve then
// reads 1, unshadowed, beyond the cascades).
// shadow.distant_occluders: level 0 again, with only the shadow occluders' occluder triangles
// (shadow.distant_plan says which), kept and refreshed as level 0 is; shadow.cull reads it to
// drop cascade casters the sun cannot see [004 §2.2.3]. A layer of its own because level 0
// holds every static caster at its coarsest level whatever its draw distance, which the
// cascades need not draw: a caster hidden behind one of those could still cast there.
// Nothing shares the last level: shadow.topdown, which frame.md allows to merge with it, looks
// straight down, not along the sun.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_distant_pass() {
  return PassDecl("shadow.distant", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.distant", Use::storage_read)
      .as("draws")
      .read("shadow.distant_data", Use::uniform_buffer)
      .read_previous("shadow.distant", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.distant_plan", Use::host)
      .write("shadow.distant", Use::depth_attachment, shadow_depth_array(kDistantLevels))
      .read_previous("shadow.distant_occluders", Use::sampled)
      .write("shadow.distant_occluders", Use::depth_attachment, shadow_depth_array(1))
      .param(distant_shadow_resolution())
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .can_disable("distant shadows disabled by settings")
      .needs("sun_above_horizon")
      .push_constants<CasterConstants>()
      .shader("shadow/distant.vert")
      .run([](PassContext& ctx) {
        const ImageExtent extent = ctx.desc("shadow.distant").extent;
        const auto data = host_records<GpuDistantLevels>(ctx.host("shadow.distant_data")).at(0);
        const auto plan = host_records<DistantPlan>(ctx.host("shadow.distant_plan")).at(0);
        const uint32_t tiles = plan.tiles_per_side, tile_texels = extent.width / tiles;
        const uint32_t all_tiles = (1u << (tiles * tiles)) - 1u;
        auto tile_rect = [&](uint32_t t) {
          return VkRect2D{{int32_t(t % tiles * tile_texels), int32_t(t / tiles * tile_texels)},
                          {tile_texels, tile_texels}};
        };
        // What a redrawn tile held is drawn again from nothing (1: no occluder).
        static constexpr VkClearAttachment kNoOccluder{VK_IMAGE_ASPECT_DEPTH_BIT, 0, {.depthStencil = {1.0f, 0}}};
        for (uint32_t level = 0; level < kDistantLevels; ++level) {
          // A level redrawn whole keeps nothing: the attachment's clear is already its start.
          if (plan.refreshed[level] != all_tiles)
            ctx.copy_layer(previous("shadow.distant"), level, "shadow.distant", level, data.refresh[level].x,
                           data.refresh[level].y);
          if (plan.refreshed[level] == 0) continue;
          ctx.begin_rendering({}, "shadow.distant", 0, level);
          bind_casters(ctx, level);
          for (uint32_t t = 0; t < tiles * tiles; ++t) {
            if (!(plan.refreshed[level] >> t & 1u)) continue;
            const uint32_t unit = level * tiles * tiles + t;
            const VkRect2D scissor = tile_rect(t);
            const VkClearRect rect{scissor, 0, 1};
            vkCmdClearAttachments(ctx.cmd(), 1, &kNoOccluder, 1, &rect);
            vkCmdSetScissor(ctx.cmd(), 0, 1, &scissor);
            draw_casters(ctx, "draws.shadow.distant", {plan.unit_first_draw[unit], plan.unit_draws[unit]});
          }
          ctx.end_rendering();
        }
        // Level 0's occluders, on the same tiles with the same move.
        if (plan.refreshed[0] != all_tiles)
          ctx.copy_layer(previous("shadow.distant_occluders"), 0, "shadow.distant_occluders", 0, data.refresh[0].x,
                         data.refresh[0].y);
        if (plan.refreshed[0] == 0) return;
        ctx.begin_rendering({}, "shadow.distant_occluders", 0, 0);
        bind_casters(ctx, 0);
        for (uint32_t t = 0; t < tiles * tiles; ++t) {
          if (!(plan.refreshed[0] >> t & 1u)) continue;
          const VkRect2D scissor = tile_rect(t);
          const VkClearRect rect{scissor, 0, 1};
          vkCmdClearAttachments(ctx.cmd(), 1, &kNoOccluder, 1, &rect);
          vkCmdSetScissor(ctx.cmd(), 0, 1, &scissor);
          draw_casters(ctx, "draws.shadow.distant", {plan.occluder_first_draw[t], plan.occluder_draws[t]});
        }
        ctx.end_rendering();
      });
}

}  // namespace nightcap
