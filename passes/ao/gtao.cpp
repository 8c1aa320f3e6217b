// ao.gtao: ground-truth-based ambient occlusion (Jimenez et al. 2016) at half resolution, from
// depth.half and normals.half: ao.bent (R8G8B8A8_UNORM, half) holds the bent normal in world
// space (rgb, 0.5·b + 0.5) and the cosine-weighted visibility (a), whose cone about b has the
// half-angle asin(√a). Slice angles and step offsets follow interleaved gradient noise of the
// pixel, shifted each frame, so that ao.temporal's history averages them; the position of a half
// texel is its footprint's centre under the frame's jittered projection. A sample's weight falls
// from 1 to 0 over the outer `falloff` share of the radius (Jimenez's and XeGTAO's falloff), and
// the depth buffer is a height field: everything behind a visible surface is solid.
// Skipped with ao.enabled=0 (frame.md: by settings only; off by default until ao.filter and
// ao.temporal land) and when nothing was drawn; skipped, ao.bent keeps its clear value, the zero
// vector and visibility 1, which occludes nothing.
#include <algorithm>
#include <array>
#include <cmath>

#include "passes/ao/gtao.glsl.h"
#include "passes/ao/kinds.h"
#include "passes/ao/stage.h"
#include "passes/core/context.h"

namespace nightcap {
namespace {

const KindRegistration kAoBent({
    .kind = kinds::ao_bent,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          const double visibility = t.raw[3];
          out["visibility"] = visibility;
          out["occlusion"] = 1.0 - visibility;
          out["cone_half_angle_deg"] = std::asin(std::sqrt(std::clamp(visibility, 0.0, 1.0))) * 180.0 / M_PI;
          const std::array<double, 3> b = {t.raw[0] * 2.0 - 1.0, t.raw[1] * 2.0 - 1.0, t.raw[2] * 2.0 - 1.0};
          const double length = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
          // The zero vector (codes 128, length under 0.01) where nothing was drawn.
          out["bent_normal"] = length > 0.1
                                   ? nlohmann::ordered_json::array({b[0] / length, b[1] / length, b[2] / length})
                                   : nlohmann::ordered_json(nullptr);
        },
    // The visibility, as grey: white is unoccluded.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::display, {t.raw[3], t.raw[3], t.raw[3]}};
        },
});

}  // namespace

PassDecl ao_gtao_pass() {
  ImageDecl bent{VK_FORMAT_R8G8B8A8_UNORM, kinds::ao_bent};
  bent.size.mode = SizeRule::Mode::output_half;
  bent.clear.color = {{128.0f / 255.0f, 128.0f / 255.0f, 128.0f / 255.0f, 1.0f}};  // the zero vector, unoccluded
  return PassDecl("ao.gtao", PassType::compute)
      .read("frame.views", Use::uniform_buffer)
      .read("frame.constants", Use::uniform_buffer)
      .read("depth.half", Use::sampled)
      .read("normals.half", Use::sampled)
      .write("ao.bent", Use::storage_write, bent)
      // Off by default until ao.filter and ao.temporal land: the composite reads ao.bent, and one
      // frame's noisy visibility is not what it is to multiply the indirect light by.
      .can_disable("ambient occlusion disabled by settings (ao.enabled=1 turns it on)", "ao", false)
      // Nothing drawn: every texel is sky, which the pass leaves unoccluded, the clear value.
      .skip_when_cleared({"depth.half", "normals.half"})
      .param_float("radius", 1.5, 0.05, 100.0, "world-space radius of the horizon search, metres")
      .param_float("falloff", 0.6, 0.01, 1.0,
                   "outer share of the radius over which an occluder's weight falls from 1 to 0")
      .param_float("max_pixels", 64.0, 1.0, 1024.0, "the most half-resolution pixels the search reaches")
      .param_int("slices", 3, 1, kGtaoMaxSlices, "directions searched per pixel")
      .param_int("steps", 4, 1, kGtaoMaxSteps, "horizon samples per side of each direction")
      .param_int("noise", 1, 0, 1,
                 "1: slice angles and step offsets vary with the pixel and the frame (interleaved gradient "
                 "noise); 0: the same for every pixel")
      .shader("ao/gtao.comp")
      .push_constants<GtaoConstants>()
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(GtaoConstants{float(ctx.param_float("radius")), float(ctx.param_float("falloff")),
                                         float(ctx.param_float("max_pixels")), float(ctx.param_int("noise")),
                                         int32_t(ctx.param_int("slices")), int32_t(ctx.param_int("steps"))});
        const ImageExtent half = ctx.desc("ao.bent").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kGtaoGroupSide), group_count(half.height, kGtaoGroupSide), 1);
      });
}

}  // namespace nightcap
