// shadow.sun_resolve (frame.md section 4): the sun's shadow in screen space, R8G8_UNORM at full
// resolution (R: visibility, filtered; G: 1, left free), before lighting.tiled reads it.
// sun_resolve.comp says how: shadow.cascades up to the last split, shadow.distant's levels beyond
// it (level 0 is the occluder there, the coarser ones further out). The filter's size is a
// specialization constant, so each size is a pipeline whose block of taps is fixed (style:
// variants are specialization constants); so is whether a cascade has a tile still waiting for
// its refresh (shadow.cull_stats says), which a frame whose cascades are whole need not test.
// Skipped with no sun above the horizon, and where nothing was drawn (scene.depth cleared): shadow.sun
// is then cleared to 1 (unshadowed), what lighting.tiled reads and, for the sky, what it computes. `enabled=0` skips it
// too (the lighting tests compare unshadowed sun light).
#include <algorithm>

#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/stage.h"
#include "passes/shadow/sun_resolve.glsl.h"

namespace nightcap {

PassDecl shadow_sun_resolve_pass() {
  ImageDecl sun{VK_FORMAT_R8G8_UNORM, kinds::mask};
  sun.clear.color = {{1.0f, 1.0f, 0.0f, 0.0f}};
  return PassDecl("shadow.sun_resolve", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("frame.views", Use::uniform_buffer)
      .read("shadow.cascade_data", Use::uniform_buffer)
      .read("scene.depth", Use::sampled)
      .read("gbuffer.normal", Use::sampled)
      .read("shadow.cascades", Use::sampled)
      .read("shadow.distant_data", Use::uniform_buffer)
      .read("shadow.distant", Use::sampled)
      .read("shadow.cull_stats", Use::host)
      .write("shadow.sun", Use::storage_write, sun)
      .param_int("filter_radius", 1, 0, 3, "the filter takes (2r + 1)² texels around the pixel's point (0: one)")
      .param_float("depth_bias", 0.5, 0, 16, "texels of light depth a receiver may lie behind the map and stay lit")
      .param_float("max_slope", 11.43, 0, 1000,
                   "largest receiver slope carried to the filter's texels (tan 85°: steeper ones self-shadow)")
      .can_disable("sun shadows disabled by settings")
      .needs("sun_above_horizon")
      .skip_when_cleared({"scene.depth"})
      .push_constants<ResolveConstants>()
      .shader("shadow/sun_resolve.comp")
      .run([](PassContext& ctx) {
        const ImageExtent size = ctx.desc("shadow.sun").extent;
        const ResolveConstants constants{float(ctx.param_float("depth_bias")), float(ctx.param_float("max_slope"))};
        int32_t check_tiles = 1;
        const std::span<const uint8_t> record = ctx.host("shadow.cull_stats");
        if (record.size() == sizeof(ShadowCullStats)) {
          const auto stats = host_records<ShadowCullStats>(record).at(0);
          check_tiles = 0;
          for (uint32_t k = 0; k < kShadowCascades; ++k)
            if (ShadowCullStats::mask(stats.complete, k) !=
                TiledMap{{}, 0.0, stats.resolution, std::max(stats.tiles_per_side, 1u)}.all())
              check_tiles = 1;
        }
        ctx.bind_pipeline({int32_t(ctx.param_int("filter_radius")), check_tiles});
        ctx.push_declared();
        ctx.push_constants(constants);
        vkCmdDispatch(ctx.cmd(), group_count(size.width, kSunResolveGroupSide),
                      group_count(size.height, kSunResolveGroupSide), 1);
      });
}

}  // namespace nightcap
