// shadow.cascades_static: the static casters' part of the sun's cascades [004 §2], kept across
// frames. shadow.cull says per cascade where its layer moved and what to redraw (and why:
// passes/shadow/cull.cpp). After a reset a layer is drawn whole from its list. Otherwise it
// starts from the previous frame's, moved by whole texels (a transfer copy,
// PassContext::copy_layer, which leaves the uncovered texels at 1: no caster); the strips the
// move uncovered are drawn under their own scissors, and each redrawn tile is cleared to 1 and
// its static casters drawn under its scissor. shadow.cascades then copies each layer and draws
// the moving casters over it. The depth test keeps the least depth whatever the order of draws,
// so the sum is the map drawn in one go. Skipped with no sun above the horizon.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_cascades_static_pass() {
  return PassDecl("shadow.cascades_static", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.cascades", Use::storage_read)
      .as("draws")
      .read("shadow.cascade_data", Use::uniform_buffer)
      .read_previous("shadow.cascades_static", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.cull_stats", Use::host)
      .write("shadow.cascades_static", Use::depth_attachment, shadow_depth_array(kShadowCascades))
      .param(sun_shadow_resolution())
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("sun_above_horizon")
      .push_constants<CasterConstants>()
      .shader("shadow/cascades.vert")
      .run([](PassContext& ctx) {
        const uint32_t resolution = ctx.desc("shadow.cascades_static").extent.width;
        const auto stats = host_records<ShadowCullStats>(ctx.host("shadow.cull_stats")).at(0);
        const uint32_t tiles = stats.tiles_per_side;
        const TiledMap map{{}, 0.0, resolution, tiles};
        const uint64_t all_tiles = map.all();
        static constexpr VkClearAttachment kNoCaster{VK_IMAGE_ASPECT_DEPTH_BIT, 0, {.depthStencil = {1.0f, 0}}};
        for (uint32_t cascade = 0; cascade < kShadowCascades; ++cascade) {
          const uint64_t refreshed = ShadowCullStats::mask(stats.refreshed, cascade);
          const uint32_t static_draws = stats.draws[cascade] - stats.moving_draws[cascade];
          if (stats.reset != uint32_t(CascadeReset::none)) {
            // Drawn whole; the attachment's clear is the layer's start.
            ctx.begin_rendering({}, "shadow.cascades_static", 0, cascade);
            bind_casters(ctx, cascade);
            draw_casters(ctx, "draws.shadow.cascades", {stats.first_draw[cascade], static_draws});
            ctx.end_rendering();
            continue;
          }
          const bool keeps = refreshed != all_tiles;
          if (keeps)
            ctx.copy_layer(previous("shadow.cascades_static"), cascade, "shadow.cascades_static", cascade,
                           stats.shift[2 * cascade], stats.shift[2 * cascade + 1]);
          const bool strips = stats.strips >> cascade & 1u;
          if (keeps && refreshed == 0 && !strips) continue;
          ctx.begin_rendering({}, "shadow.cascades_static", 0, cascade);
          bind_casters(ctx, cascade);
          auto scissor_of = [](const MapTexels& r) {
            return VkRect2D{{r.x0, r.y0}, {uint32_t(r.x1 - r.x0), uint32_t(r.y1 - r.y0)}};
          };
          if (strips) {
            // copy_layer left them at 1.
            const UncoveredStrips uncovered =
                uncovered_strips(resolution, {stats.shift[2 * cascade], stats.shift[2 * cascade + 1]});
            uint32_t first = stats.strip_first_draw[cascade];
            for (uint32_t axis = 0; axis < 2; ++axis) {
              const MapTexels& part = axis == 0 ? uncovered.columns : uncovered.rows;
              const uint32_t count = stats.strip_draws[2 * cascade + axis];
              if (part.empty() || count == 0) {
                first += count;
                continue;
              }
              const VkRect2D scissor = scissor_of(part);
              vkCmdSetScissor(ctx.cmd(), 0, 1, &scissor);
              draw_casters(ctx, "draws.shadow.cascades", {first, count});
              first += count;
            }
          }
          for (uint32_t t = 0; t < tiles * tiles; ++t) {
            if (!(refreshed >> t & 1u)) continue;
            const uint32_t unit = cascade * tiles * tiles + t;
            const VkRect2D scissor = scissor_of(map.tile_texels(t));
            const VkClearRect rect{scissor, 0, 1};
            vkCmdClearAttachments(ctx.cmd(), 1, &kNoCaster, 1, &rect);
            vkCmdSetScissor(ctx.cmd(), 0, 1, &scissor);
            draw_casters(ctx, "draws.shadow.cascades", {stats.unit_first_draw[unit], stats.unit_draws[unit]});
          }
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
