// shadow.local_moments (frame.md section 1, shadow.local [000][001]): each spot light's depth
// map turned into the moments of t, the linear depth along the light's axis mapped to [0, 1]
// between the map's near plane and the light's range, filtered by a (2r + 1)² box blur, into an
// RGBA16_UNORM array (one layer per map) that lighting.tiled reads. How many moments is
// shadow.local_plan's `moments` (recorded in shadow.local_data's counts.y, which lighting.tiled
// reads too, so the two cannot disagree, in a frame or a replay):
// - 4 (the default): moment shadow maps (Peters and Klein 2015), E[(t, t², t³, t⁴)] through the
//   paper's quantization transform (local_moments.glsl); lighting.tiled reconstructs with
//   Hamburger 4MSM. Deviation from frame.md (2-moment VSM, R16G16_UNORM): under two stacked
//   occluders VSM lets half the light through the umbra even with light-bleeding reduction,
//   4MSM with it none (accuracy.md asks ≤ 2%; LocalShadows.StackedOccludersLeak).
// - 2: variance shadow maps, (E[t], E[t²]) in .rg, .ba 0; lighting.tiled's Chebyshev bound.
// One RGBA16_UNORM resource for both rather than an R16G16_UNORM one beside it: a resource's
// format is fixed by its declaration, and a second array would be bound, cleared and recorded
// in every frame while only one is written; VSM pays for the two unused channels.
// The blur is separable and done in one dispatch per map: a workgroup loads its kLocalMomentsTile² tile and
// an r-texel apron into shared memory, sums rows, then columns. Linear t rather than the stored
// perspective depth: the moments' variance only measures how far apart two surfaces are when
// the depth is linear. Layers without a map hold the moments of t = 1 (nothing in front of the
// far plane, lit), by a transfer clear. A map whose slot kept its static depth since the previous
// frame's map of it (shadow.local_plan's moments_from) copies that map's moments and computes
// again only the tiles moving casters cover now or did then, grown by the blur (moments_dirty); `blur_radius` is taken
// to stay the same over a run (the plan cannot see it). Skipped with shadow.local.
#include <algorithm>
#include <cmath>

#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/stage.h"

namespace nightcap {

// The quantization transform shared with the shaders, for the empty layers' clear value: the
// GLSL is valid C++ over glm's types.
namespace local_moments_glsl {
using glm::mat4;
using glm::vec4;
#include "passes/shadow/local_moments.glsl"
}  // namespace local_moments_glsl

PassDecl shadow_local_moments_pass() {
  ImageDecl moments{VK_FORMAT_R16G16B16A16_UNORM, kinds::lookup_table};
  moments.size.mode = SizeRule::Mode::like;
  moments.size.like = "shadow.local";
  moments.layers = kLocalShadowSlices;
  // What a skipped pass leaves: read by no light (lighting.tiled reads only the layers of maps).
  moments.clear.color = {{1.0f, 1.0f, 0.0f, 0.0f}};
  return PassDecl("shadow.local_moments", PassType::compute)
      .read("shadow.local_data", Use::uniform_buffer)
      .read("shadow.local", Use::sampled)
      .read("shadow.local_plan", Use::host)
      .read_previous("shadow.local_moments", Use::sampled)
      .write("shadow.local_moments", Use::storage_write, moments)
      .param_int("blur_radius", 1, 0, kLocalShadowMaxBlur, "the box blur takes (2r + 1)² texels (0: none)")
      .needs("spot_lights")
      .push_constants<LocalMomentsDispatch>()
      .shader("shadow/local_moments.comp")
      .run([](PassContext& ctx) {
        const auto plan = host_records<LocalShadowPlan>(ctx.host("shadow.local_plan")).at(0);
        const int32_t moments = local_shadow_moments(ctx.host("shadow.local_data"), "shadow.local_moments");
        const uint32_t side = ctx.desc("shadow.local_moments").extent.width,
                       groups = group_count(side, kLocalMomentsTile);
        // Maps whose moments the previous frame has but where moving casters are or were (the
        // plan says which): copied, then computed again over that part alone.
        const uint32_t maps = std::min(plan.maps, kLocalShadowSlices);
        const int32_t blur = int32_t(ctx.param_int("blur_radius"));
        bool dispatched = false;
        // Tiles [x0, x1) × [y0, y1) of layers [first, first + layers).
        auto dispatch = [&](uint32_t first, uint32_t layers, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
          // Disjoint layers or tiles, but the validation's synchronization checks see the whole bound image.
          if (dispatched) ctx.storage_barrier();
          ctx.bind_pipeline({blur, moments});
          ctx.push_declared();
          ctx.push_constants(LocalMomentsDispatch{first, x0, y0, 0});
          vkCmdDispatch(ctx.cmd(), x1 - x0, y1 - y0, layers);
          dispatched = true;
        };
        std::vector<bool> copied(maps, false);
        for (uint32_t map = 0; map < maps; ++map) {
          const int32_t from = plan.moments_from[map];
          if (from < 0) continue;
          if (uint32_t(from) >= kLocalShadowSlices)
            throw GraphError("shadow.local_moments: shadow.local_plan takes map " + std::to_string(map) +
                             "'s moments from layer " + std::to_string(from));
          ctx.copy_layer(previous("shadow.local_moments"), uint32_t(from), "shadow.local_moments", map);
          copied[map] = true;
        }
        for (uint32_t map = 0; map < maps; ++map) {
          const glm::vec4 dirty = plan.moments_dirty[map];
          if (!copied[map] || !(dirty.x <= dirty.z && dirty.y <= dirty.w)) continue;
          // The texels the moving casters cover, and those whose blur reaches them.
          auto texel = [&](float ndc, int32_t grow) {
            return std::clamp(int32_t(std::floor((double(ndc) * 0.5 + 0.5) * side)) + grow, 0, int32_t(side) - 1);
          };
          const int32_t x0 = texel(dirty.x, -blur - 1), x1 = texel(dirty.z, blur + 1);
          const int32_t y0 = texel(dirty.y, -blur - 1), y1 = texel(dirty.w, blur + 1);
          dispatch(map, 1, uint32_t(x0) / kLocalMomentsTile, uint32_t(y0) / kLocalMomentsTile,
                   uint32_t(x1) / kLocalMomentsTile + 1, uint32_t(y1) / kLocalMomentsTile + 1);
        }
        // The others whole, a dispatch per run of consecutive maps.
        for (uint32_t first = 0; first < maps;) {
          if (copied[first]) {
            ++first;
            continue;
          }
          uint32_t end = first;
          while (end < maps && !copied[end]) ++end;
          dispatch(first, end - first, 0, 0, groups, groups);
          first = end;
        }
        // The empty layers: the stored moments of t = 1 (nothing in front of the far plane), cleared.
        VkClearValue lit{};
        const glm::vec4 stored =
            moments == 4 ? local_moments_glsl::encode_moments(glm::vec4(1.0f)) : glm::vec4(1.0f, 1.0f, 0.0f, 0.0f);
        for (int c = 0; c < 4; ++c) lit.color.float32[c] = stored[c];
        ctx.clear_layers("shadow.local_moments", maps, kLocalShadowSlices - maps, lit);
      });
}

}  // namespace nightcap
