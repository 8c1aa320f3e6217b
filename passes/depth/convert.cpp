// depth.convert: device depth → depth.linear (R32_SFLOAT, metres along the view axis), the form
// every later stage samples, and at half resolution depth.half (R16_SFLOAT metres) and
// stencil.half (R8_UINT tags) for the half-resolution passes. frame.md says never skipped; the
// geometry stage's rule wins: when nothing was drawn (scene.depth cleared) the outputs are the
// sky everywhere, which their clear values hold.
//
// A half texel takes both its depth and its stencil from one texel of its 2×2 footprint, the one
// nearest to the camera (depth/half_footprint.glsl, which normals.half follows too): the pair
// then describes one surface, and thin foreground (hair, foliage, poles) survives the downsample
// instead of the sky behind it. Averaging depths would invent surfaces between silhouettes, and a
// min or max of stencil bits would invent classes.
// A compute pass writes all three: the full and half outputs have different sizes, which one
// render pass cannot draw into.
#include <limits>

#include "passes/core/context.h"
#include "passes/depth/convert.glsl.h"
#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/scene/stencil_tags.h"

namespace nightcap {
namespace {

// stencil.half: the tag of one full-resolution texel.
const KindRegistration kStencil({
    .kind = kinds::stencil,
    .describe = [](const TexelValues& t, const KindFrame&,
                   nlohmann::ordered_json& out) { describe_stencil_tag(uint32_t(t.codes.at(0)), out); },
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          const std::array<uint8_t, 3> c = stencil_colour(uint32_t(t.codes.at(0)));
          return TexelPicture{TexelPicture::Scale::display, {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0}};
        },
});

}  // namespace

PassDecl depth_convert_pass() {
  ImageDecl linear{VK_FORMAT_R32_SFLOAT, kinds::linear_depth};
  linear.clear.color = {{float(kSkyDepth), 0, 0, 0}};
  ImageDecl half_depth{VK_FORMAT_R16_SFLOAT, kinds::linear_depth};
  half_depth.size.mode = SizeRule::Mode::output_half;
  half_depth.clear.color = {{65504.0f, 0, 0, 0}};  // the sky clamped to the largest finite half
  ImageDecl half_stencil{VK_FORMAT_R8_UINT, kinds::stencil};
  half_stencil.size.mode = SizeRule::Mode::output_half;
  return PassDecl("depth.convert", PassType::compute)
      .read("frame.views", Use::uniform_buffer)
      .read("scene.depth", Use::sampled)
      .aspects("scene.depth", {ViewAspect::depth, ViewAspect::stencil})
      .write("depth.linear", Use::storage_write, linear)
      .write("depth.half", Use::storage_write, half_depth)
      .write("stencil.half", Use::storage_write, half_stencil)
      .param_float("sky_depth", kSkyDepth, 1.0, std::numeric_limits<float>::max(),
                   "linear depth written where nothing was drawn (finite, so no Inf)")
      .skip_when_cleared({"scene.depth"}, [](const ParamValues& p) { return p.at("sky_depth") == kSkyDepth; })
      .compare("depth.linear", ComparisonContract::depth(0x1p-23,
                                                         "znear / depth is correctly rounded (0.5 ULP, "
                                                         "tests/unit/depth_convert_test.cpp): two devices "
                                                         "agree to 1 ULP"))
      .compare("depth.half", ComparisonContract::depth(0x1p-10,
                                                       "the nearest half to depth.linear, which two devices "
                                                       "give 1 float ULP apart: the halves may then round "
                                                       "to neighbours, 1 half ULP (at most 2⁻¹⁰ relative)"))
      .shader("depth/convert.comp")
      .push_constants<DepthConvertConstants>()
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(DepthConvertConstants{float(ctx.param_float("sky_depth"))});
        const ImageExtent half = ctx.desc("depth.half").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kDepthConvertGroupSide),
                      group_count(half.height, kDepthConvertGroupSide), 1);
      });
}

}  // namespace nightcap
