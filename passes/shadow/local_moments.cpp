// shadow.local_moments (frame.md section 1, shadow.local [000][001]): each spot light's depth
// map turned into variance shadow map moments (E[t], E[t²] of t, the linear depth along the
// light's axis mapped to [0, 1] between the map's near plane and the light's range), filtered
// by a (2r + 1)² box blur, into an R16G16_UNORM array (one layer per map) that lighting.tiled
// filters with Chebyshev's inequality. The blur is separable and done in one dispatch per map:
// a workgroup loads its 16×16 tile and an r-texel apron into shared memory, sums rows, then
// columns. Linear t rather than the stored perspective depth: the moments' variance only
// measures how far apart two surfaces are when the depth is linear. Layers without a map hold
// (1, 1): nothing in front of the far plane, lit. Skipped with shadow.local.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/local_layout.h"

namespace nightcap {

PassDecl shadow_local_moments_pass() {
  ImageDecl moments{VK_FORMAT_R16G16_UNORM, ResourceKind::lookup_table};
  moments.size.mode = SizeRule::Mode::like;
  moments.size.like = "shadow.local";
  moments.layers = kLocalShadowSlices;
  moments.clear.color = {{1.0f, 1.0f, 0.0f, 0.0f}};
  return PassDecl("shadow.local_moments", PassType::compute)
      .read("shadow.local_data", Use::uniform_buffer)
      .read("shadow.local", Use::sampled)
      .read("shadow.local_plan", Use::host)
      .write("shadow.local_moments", Use::storage_write, moments)
      .param("blur_radius", 1, 0, kLocalShadowMaxBlur, "the box blur takes (2r + 1)² texels (0: none)")
      .needs("spot_lights")
      .push_constants<uint32_t>()
      .shader("shadow/local_moments.comp")
      .run([](PassContext& ctx) {
        const auto plan = host_records<LocalShadowPlan>(ctx.host("shadow.local_plan")).at(0);
        const uint32_t side = ctx.desc("shadow.local_moments").extent.width, groups = (side + 15) / 16;
        const std::vector<Binding> bindings{
            Binding::uniform(ctx.slot("shadow.local_data"), "shadow.local_data"),
            Binding::texture(ctx.slot("shadow.local"), "shadow.local", ctx.nearest_clamp(), ViewAspect::depth),
            Binding::image(ctx.slot("shadow.local_moments"), "shadow.local_moments", 0)};
        // The maps with their blur; the empty layers filled with (1, 1) by a pipeline of their own.
        const uint32_t maps = std::min(plan.maps, kLocalShadowSlices);
        if (maps > 0) {
          ctx.bind_pipeline({int32_t(ctx.param("blur_radius")), 0});
          ctx.push(bindings);
          ctx.push_constants(uint32_t(0));
          vkCmdDispatch(ctx.cmd(), groups, groups, maps);
        }
        if (maps < kLocalShadowSlices) {
          // Disjoint layers, but the validation's synchronization checks see the whole bound image.
          if (maps > 0) ctx.storage_barrier();
          ctx.bind_pipeline({0, 1});
          ctx.push(bindings);
          ctx.push_constants(maps);
          vkCmdDispatch(ctx.cmd(), groups, groups, kLocalShadowSlices - maps);
        }
      });
}

}  // namespace nightcap
