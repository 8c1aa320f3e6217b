// shadow.local (frame.md section 1, [004 §3]): the depth of each spot light's shadow map, one
// layer of a D32 2D array per map that shadow.local_plan chose, each drawn from its own range
// of draws.shadow.local (no layer routing in a geometry shader [001]). D32, forward (0 at the
// near plane, LESS): a perspective depth crowds its precision near the light, and D16 would
// leave centimetre steps at a street light's range. Casters are drawn from both sides (an open
// mesh still casts); the bias is the lookup's. Layers without a map keep the clear (1: nothing).
// shadow.local_moments turns the depth into the moments lighting.tiled filters. Skipped with no
// spot light in the scene; a frame whose spot lights are all out of view draws nothing.
#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/local_layout.h"

namespace nightcap {

PassDecl shadow_local_pass() {
  ImageDecl map{VK_FORMAT_D32_SFLOAT, ResourceKind::lookup_table};
  map.size.mode = SizeRule::Mode::square_param;
  map.size.param = "resolution";
  map.layers = kLocalShadowSlices;
  map.clear.depthStencil = {1.0f, 0};
  return PassDecl("shadow.local", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.local", Use::storage_read)
      .read("shadow.local_data", Use::uniform_buffer)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.local_plan", Use::host)
      .write("shadow.local", Use::depth_attachment, map)
      .param("resolution", kLocalShadowResolution, 64, 2048, "texels per side of each map")
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .needs("spot_lights")
      .push_constants<uint32_t>()
      .shader("shadow/local.vert")
      .run([](PassContext& ctx) {
        const auto plan = host_records<LocalShadowPlan>(ctx.host("shadow.local_plan")).at(0);
        for (uint32_t slice = 0; slice < kLocalShadowSlices; ++slice) {
          ctx.begin_rendering({}, "shadow.local", 0, slice);
          if (slice < plan.maps && plan.slice_draws[slice] > 0) {
            ctx.bind_pipeline();
            std::vector<Binding> bindings = geometry_bindings(ctx, "draws.shadow.local");
            bindings.push_back(Binding::uniform(ctx.slot("shadow.local_data"), "shadow.local_data"));
            ctx.push(bindings);
            ctx.push_constants(slice);
            draw_scene(ctx, "draws.shadow.local", [](uint32_t, const GpuMaterial&) {},
                       {plan.slice_first_draw[slice], plan.slice_draws[slice]});
          }
          ctx.end_rendering();
        }
      });
}

}  // namespace nightcap
