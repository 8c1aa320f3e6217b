// shadow.cascades_static: the static casters' part of the sun's cascades [004 §2], kept across
// frames. shadow.cull says per cascade whether the previous frame's layer still holds (its
// projection and culling volume unchanged, history valid: ShadowCullStats::static_source); such a
// layer is copied from history (a transfer copy: PassContext::copy_layer), any other is cleared
// and its static casters drawn. shadow.cascades then copies each layer and draws the moving casters over it. The depth
// test keeps the least depth whatever the order of draws, so the sum is the map drawn in one go, bit for bit. Skipped
// with no sun above the horizon.
#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap {

PassDecl shadow_cascades_static_pass() {
  ImageDecl map{VK_FORMAT_D32_SFLOAT, ResourceKind::lookup_table};
  map.size.mode = SizeRule::Mode::square_param;
  map.size.param = "resolution";
  map.layers = kShadowCascades;
  map.clear.depthStencil = {1.0f, 0};
  return PassDecl("shadow.cascades_static", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.cascades", Use::storage_read)
      .read("shadow.cascade_data", Use::uniform_buffer)
      .read_previous("shadow.cascades_static", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.cull_stats", Use::host)
      .write("shadow.cascades_static", Use::depth_attachment, map)
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
          ctx.bind_pipeline();
          std::vector<Binding> bindings = geometry_bindings(ctx, "draws.shadow.cascades");
          bindings.push_back(Binding::uniform(ctx.slot("shadow.cascade_data"), "shadow.cascade_data"));
          ctx.push(bindings);
          ctx.push_constants(cascade);
          draw_scene(ctx, "draws.shadow.cascades", [](uint32_t, const GpuMaterial&) {},
                     {stats.first_draw[cascade], stats.draws[cascade] - stats.moving_draws[cascade]});
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
