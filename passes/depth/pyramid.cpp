// depth.pyramid: min and max linear depth over every footprint, from half resolution down to
// 1×1 (R32G32_SFLOAT, a full mip chain). Culling and clustering read it, so it must be
// conservative: odd sizes fold their last row and column into the neighbouring texel. Never
// skipped (frame.md).
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl depth_pyramid_pass() {
  ImageDecl pyramid{VK_FORMAT_R32G32_SFLOAT, ResourceKind::depth_minmax};
  pyramid.size.mode = SizeRule::Mode::output_half;
  pyramid.mips = 0;
  return PassDecl("depth.pyramid", PassType::compute)
      .read("depth.linear", Use::sampled)
      .write("depth.pyramid", Use::storage_write, pyramid)
      .shader("depth/pyramid.comp")
      .run([](PassContext& ctx) {
        ComputePipelineDesc desc;
        desc.shader = "depth/pyramid.comp";
        desc.bindings = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                         VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        desc.push_constant_bytes = 20;
        ctx.bind(desc);
        const ImageExtent full = ctx.desc("depth.linear").extent;
        const ImageExtent levels = ctx.desc("depth.pyramid").extent;
        for (uint32_t mip = 0; mip < levels.mips; ++mip) {
          struct {
            int32_t source[2], target[2], from_linear;
          } params{};
          params.source[0] = int32_t(mip == 0 ? full.width : mip_size(levels.width, mip - 1));
          params.source[1] = int32_t(mip == 0 ? full.height : mip_size(levels.height, mip - 1));
          params.target[0] = int32_t(mip_size(levels.width, mip));
          params.target[1] = int32_t(mip_size(levels.height, mip));
          params.from_linear = mip == 0;
          // Level 0 binds level 0 as its (unused) source: every binding must be valid.
          ctx.push({Binding::texture(0, "depth.linear", ctx.nearest_clamp()),
                    Binding::image(1, "depth.pyramid", mip == 0 ? 0 : int(mip) - 1),
                    Binding::image(2, "depth.pyramid", int(mip))});
          ctx.push_constants(&params, sizeof(params));
          vkCmdDispatch(ctx.cmd(), (params.target[0] + 7) / 8, (params.target[1] + 7) / 8, 1);
          ctx.storage_barrier();
        }
      });
}

}  // namespace nightcap
