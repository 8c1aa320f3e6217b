// bloom.levelN: level N of bloom.chain (RGBA16F, half the output size, 6 mips), the 2×2 box
// average of level N − 1 — of `lit` for level 0, the colour the frame's assembly names —
// blurred by a separable Gaussian of `sigma` texels of that level (frame.md: a 6-level
// downsample chain with separable blurs). Each level is its own pass: it samples mip N − 1 of
// bloom.chain while it writes mip N, and the graph places the barrier between them. `tonemap`
// adds the levels. A NaN in `lit` contributes nothing and +Inf counts as 65504, so the
// chain is always finite. At small outputs the chain is shorter (a 1×1 image has one mip): the
// levels beyond it are skipped.
#include <algorithm>
#include <cmath>

#include "passes/core/context.h"
#include "passes/post/bloom.glsl.h"
#include "passes/post/stage.h"

namespace nightcap {
namespace {

BloomConstants constants(double sigma, const ImageExtent& source, uint32_t source_mip, const ImageExtent& chain,
                         uint32_t level) {
  BloomConstants c{};
  c.source_size[0] = int32_t(mip_size(source.width, source_mip));
  c.source_size[1] = int32_t(mip_size(source.height, source_mip));
  c.target_size[0] = int32_t(mip_size(chain.width, level));
  c.target_size[1] = int32_t(mip_size(chain.height, level));
  c.radius = std::min(kBloomMaxRadius, int(std::ceil(3.0 * sigma)));
  double weights[kBloomMaxRadius + 1], total = 0;
  for (int k = 0; k <= c.radius; ++k) {
    weights[k] = std::exp(-0.5 * k * k / (sigma * sigma));
    total += k == 0 ? weights[k] : 2 * weights[k];
  }
  for (int k = 0; k <= c.radius; ++k) c.weights[k] = float(weights[k] / total);
  return c;
}

// What a level stores where its source is uniform with value `source`: radiance()'s NaN and
// range rule, then the same half. The 2×2 box of equal halves is exact in float, and the blur's
// weights sum to 1 within a few float ULPs, far less than the half ULP nearest_half would need
// to move off that half; alpha is 1.
VkClearValue uniform_level(const VkClearValue& source) {
  VkClearValue level{};
  const float* c = source.color.float32;
  const bool nan = std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2]);
  for (int k = 0; k < 3; ++k) level.color.float32[k] = nan ? 0.0f : half_rounded(std::clamp(c[k], 0.0f, 65504.0f));
  level.color.float32[3] = 1.0f;
  return level;
}

}  // namespace

PassDecl bloom_level_pass(uint32_t level, const std::string& lit) {
  const std::string source = level == 0 ? lit : "bloom.chain";
  const uint32_t source_mip = level == 0 ? 0 : level - 1;
  PassDecl pass("bloom.level" + std::to_string(level), PassType::compute);
  if (level == 0) {
    ImageDecl chain{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
    chain.size.mode = SizeRule::Mode::output_half;
    chain.mips = kBloomLevels;
    pass.read(lit, Use::sampled).as("source").write("bloom.chain", Use::storage_write, chain, Subresources::mip(0));
  } else {
    pass.read("bloom.chain", Use::sampled, Subresources::mip(level - 1))
        .as("source")
        .modify("bloom.chain", Use::storage_write, Subresources::mip(level));
  }
  return pass.can_disable("bloom disabled by settings", "bloom")
      .param_float("sigma", 1.5, 0.25, 2.6,
                   "Gaussian blur of each level, in texels of that level (radius ceil(3 sigma) <= 8)")
      .skip_when([level](const SkipContext& frame) -> std::string {
        const uint32_t levels = std::min(kBloomLevels, full_mip_count((frame.width + 1) / 2, (frame.height + 1) / 2));
        if (level < levels) return "";
        return "bloom.chain has " + std::to_string(levels) + (levels == 1 ? " level" : " levels") + " at " +
               std::to_string(frame.width) + "x" + std::to_string(frame.height);
      })
      .fold_when_uniform({source},
                         [source](const UniformValues& inputs, const ParamValues&) -> std::optional<UniformValues> {
                           return UniformValues{{"bloom.chain", uniform_level(inputs.at(source))}};
                         })
      .shader("post/bloom.comp")
      .push_constants<BloomConstants>()
      .compare("bloom.chain",
               ComparisonContract::floats(0x1p-24, 0x1p-7,
                                          "each level is within one half ULP of its filter of the level above "
                                          "(tests/unit/bloom_test.cpp) and carries the levels above it: six levels "
                                          "on two devices erring apart, twelve half ULPs"))
      .run([level, source, source_mip](PassContext& ctx) {
        ctx.bind_pipeline();
        const BloomConstants c = constants(ctx.param_float("sigma"), ctx.desc(source).extent, source_mip,
                                           ctx.desc("bloom.chain").extent, level);
        ctx.push_declared();
        ctx.push_constants(c);
        vkCmdDispatch(ctx.cmd(), group_count(c.target_size[0], kBloomTile), group_count(c.target_size[1], kBloomTile),
                      1);
      });
}

}  // namespace nightcap
