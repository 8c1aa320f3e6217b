// depth.pyramid: min and max linear depth over every footprint, from half resolution down to
// 1×1 (R32G32_SFLOAT, a full mip chain). Culling and clustering read it, so it must be
// conservative: odd sizes fold their last row and column into the neighbouring texel. frame.md
// says never skipped; when depth.linear is cleared (the sky everywhere) the pyramid is too, and
// its clear value is that sky.
#include "passes/core/context.h"
#include "passes/depth/kinds.h"
#include "passes/depth/pyramid.glsl.h"
#include "passes/depth/stage.h"

namespace nightcap {
namespace {

const KindRegistration kDepthMinMax({
    .kind = kinds::depth_minmax,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["min_m"] = t.raw[0];
          out["max_m"] = t.raw[1];
        },
    // A footprint of sky alone (depth.linear's default sky depth) is drawn as nothing there, as
    // linear_depth draws the sky.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::distance, {t.raw[0] < kSkyDepth ? t.raw[0] : 0.0, 0, 0}};
        },
});

}  // namespace

PassDecl depth_pyramid_pass() {
  ImageDecl pyramid{VK_FORMAT_R32G32_SFLOAT, kinds::depth_minmax};
  pyramid.size.mode = SizeRule::Mode::output_half;
  pyramid.mips = 0;
  pyramid.clear.color = {{float(kSkyDepth), float(kSkyDepth), 0, 0}};
  return PassDecl("depth.pyramid", PassType::compute)
      .read("depth.linear", Use::sampled)
      .write("depth.pyramid", Use::storage_write, pyramid)
      .skip_when_cleared({"depth.linear"})
      .level_mips("depth.pyramid", {-1, 0})  // the level above the one written (level 0: unused), and that one
      .push_constants<PyramidConstants>()
      .shader("depth/pyramid.comp")
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        const ImageExtent full = ctx.desc("depth.linear").extent;
        const ImageExtent levels = ctx.desc("depth.pyramid").extent;
        for (uint32_t mip = 0; mip < levels.mips; ++mip) {
          PyramidConstants params{};
          params.source_size[0] = int32_t(mip == 0 ? full.width : mip_size(levels.width, mip - 1));
          params.source_size[1] = int32_t(mip == 0 ? full.height : mip_size(levels.height, mip - 1));
          params.target_size[0] = int32_t(mip_size(levels.width, mip));
          params.target_size[1] = int32_t(mip_size(levels.height, mip));
          params.from_linear = mip == 0;
          ctx.push_declared(mip);
          ctx.push_constants(params);
          vkCmdDispatch(ctx.cmd(), group_count(params.target_size[0], kPyramidGroupSide),
                        group_count(params.target_size[1], kPyramidGroupSide), 1);
          ctx.storage_barrier();
        }
      });
}

}  // namespace nightcap
