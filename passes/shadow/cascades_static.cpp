// shadow.cascades_static: the static casters' part of the sun's cascades [004 §2], kept across
// frames. shadow.cull says per cascade whether the previous frame's layer still holds (its
// projection and culling volume unchanged, history valid: ShadowCullStats::static_source); such a
// layer is copied from history (a transfer copy: PassContext::copy_layer), any other is cleared
// and its static casters drawn. shadow.cascades then copies each layer and draws the moving casters over it. The depth
// test keeps the least depth whatever the order of draws, so the sum is the map drawn in one go, bit for bit. Skipped
// with no sun above the horizon.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap {

PassDecl shadow_cascades_static_pass() {
  return PassDecl("shadow.cascades_static", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.cascades", Use::storage_read)
      .read("shadow.cascade_data", Use::uniform_buffer)
      .read_previous("shadow.cascades_static", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.cull_stats", Use::host)
      .write("shadow.cascades_static", Use::depth_attachment, shadow_depth_array(kShadowCascades))
      .param("resolution", kShadowResolution, 64, 4096,
             "texels per side of each cascade (shadow.cascades' too): shadow.cull.resolution's")
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("sun_above_horizon")
      .push_constants<uint32_t>()
      .shader("shadow/cascades.vert")
      .run([](PassContext& ctx) {
        const auto data = host_records<GpuShadowCascades>(ctx.host("shadow.cascade_data")).at(0);
        const uint32_t resolution = ctx.desc("shadow.cascades_static").extent.width;
        if (uint32_t(data.light_direction.w) != resolution)
          throw GraphError("shadow.cascades_static: its resolution (" + std::to_string(resolution) +
                           ") is not shadow.cull's (" + std::to_string(uint32_t(data.light_direction.w)) +
                           "): set shadow.cull.resolution and shadow.cascades_static.resolution alike");
        const auto stats = host_records<ShadowCullStats>(ctx.host("shadow.cull_stats")).at(0);
        for (uint32_t cascade = 0; cascade < kShadowCascades; ++cascade) {
          if (stats.static_source[cascade] == uint32_t(ShadowStaticSource::reused)) {
            ctx.copy_layer(previous("shadow.cascades_static"), cascade, "shadow.cascades_static", cascade);
            continue;
          }
          ctx.begin_rendering({}, "shadow.cascades_static", 0, cascade);
          bind_casters(ctx, "draws.shadow.cascades", "shadow.cascade_data", cascade);
          draw_casters(ctx, "draws.shadow.cascades",
                       {stats.first_draw[cascade], stats.draws[cascade] - stats.moving_draws[cascade]});
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
