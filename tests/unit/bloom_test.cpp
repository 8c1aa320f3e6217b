// bloom.level0…5 run as a graph (each level sampling the one above in bloom.chain) against the
// double-precision filter of tests/reference/bloom_reference.h.
//
// Bound per level, given the level above as the GPU stored it: |GPU − exact| ≤ (2⁻¹¹ + 2⁻¹⁸)·exact
// + 2⁻²⁵. The pass stores nearest_half of its float result: half a half-ULP is at most 2⁻¹¹ of
// the value for normal halves and 2⁻²⁵ absolute below them. The float result itself is a sum of
// non-negative terms whose longest chain of roundings, at the largest radius (8), is 55
// (3 in the box, 1 per weight, 3 per tap pair and 1 for the centre in each of the two blurs),
// so it is within 55·2⁻²⁴ < 2⁻¹⁸ of the exact filter of the same inputs.
// Over the whole chain, against the exact filter applied level after level without rounding:
// every level is a convex combination of the one above (weights ≥ 0 summing to 1), so relative
// errors of its inputs carry over unchanged and level N holds N + 1 roundings:
// (1 + e)^(N+1) − 1 relative with e = 2⁻¹¹ + 2⁻¹⁸, plus (N + 1)·2⁻²⁵ absolute.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/post/stage.h"
#include "tests/reference/bloom_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using reference::RgbImage;

constexpr double kLevelRel = 0x1p-11 + 0x1p-18, kLevelAbs = 0x1p-25;

struct ChainRun {
  std::vector<PassDecl> passes;
  CompiledGraph graph;
  Execution execution;

  const CompiledPass& pass(uint32_t level) const {
    for (const CompiledPass& p : graph.passes)
      if (p.decl->name == "bloom.level" + std::to_string(level)) return p;
    throw std::runtime_error("no level " + std::to_string(level));
  }
  const VersionData& chain() const { return *execution.final_version("bloom.chain"); }
};

class Bloom : public GpuTest {
 protected:
  // The bloom passes of the frame on `lit` (RGBA16F texels, 4 floats each) at width×height.
  static ChainRun run_chain(const std::vector<float>& lit, uint32_t width, uint32_t height,
                            const ParamOverrides& params = {}) {
    ChainRun run;
    for (uint32_t level = 0; level < kBloomLevels; ++level)
      run.passes.push_back(bloom_level_pass(level, "lighting.lit"));
    ResourceDesc desc;
    desc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    desc.kind = kinds::hdr_colour;
    desc.extent.width = width;
    desc.extent.height = height;
    auto bytes = std::make_shared<std::vector<uint8_t>>(lit.size() * 2);
    for (size_t i = 0; i < lit.size(); ++i) {
      const uint16_t h = float_to_half(lit[i]);
      std::memcpy(bytes->data() + 2 * i, &h, 2);
    }
    GraphSettings settings;
    settings.width = width;
    settings.height = height;
    settings.sinks = {"bloom.chain"};
    settings.capture = true;
    settings.params = params;
    run.graph = compile_graph(run.passes, {{"lighting.lit", desc}}, settings);
    ExecutionOptions options;
    options.shaders = builtin_shaders();
    run.execution = execute_graph(*gpu_, *cache_, run.graph, {{"lighting.lit", bytes}}, options);
    return run;
  }

  // Worst |gpu − exact| / (rel·exact + abs) over a level, and checks alpha is 1 and every value
  // finite.
  static double worst_ratio(const VersionData& chain, uint32_t mip, const RgbImage& exact, double rel, double abs) {
    const RgbImage gpu = reference::decode_rgba16f(*chain.bytes, chain.desc.extent, mip);
    EXPECT_EQ(gpu.width, exact.width);
    EXPECT_EQ(gpu.height, exact.height);
    double worst = 0;
    for (size_t i = 0; i < gpu.texels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double g = gpu.texels[i][c], e = exact.texels[i][c];
        EXPECT_TRUE(std::isfinite(g)) << "mip " << mip << " texel " << i;
        worst = std::max(worst, std::abs(g - e) / (rel * e + abs));
      }
    return worst;
  }

  // Each level against the exact filter of the level above as stored, and the chain against
  // the exact filter all the way down; returns the worst per-level ratio to its bound.
  static double check_levels(const ChainRun& run, const RgbImage& lit, double sigma) {
    const VersionData& chain = run.chain();
    const ImageExtent& e = chain.desc.extent;
    double worst_level = 0, worst_chain = 0;
    RgbImage exact_above = lit;
    for (uint32_t level = 0; level < e.mips; ++level) {
      const RgbImage above = level == 0 ? lit : reference::decode_rgba16f(*chain.bytes, e, level - 1);
      const uint32_t w = mip_size(e.width, level), h = mip_size(e.height, level);
      const double ratio = worst_ratio(chain, level, reference::bloom_level(above, w, h, sigma), kLevelRel, kLevelAbs);
      EXPECT_LE(ratio, 1.0) << "level " << level;
      worst_level = std::max(worst_level, ratio);
      exact_above = reference::bloom_level(exact_above, w, h, sigma);
      const double chain_ratio =
          worst_ratio(chain, level, exact_above, std::pow(1 + kLevelRel, level + 1) - 1, (level + 1) * kLevelAbs);
      EXPECT_LE(chain_ratio, 1.0) << "level " << level << " against the unrounded chain";
      worst_chain = std::max(worst_chain, chain_ratio);
    }
    std::printf("bloom %ux%u, %u levels: worst level %.3f of its bound, worst chain %.3f of its bound\n", e.width,
                e.height, e.mips, worst_level, worst_chain);
    return worst_level;
  }

  static RgbImage as_image(const std::vector<float>& lit, uint32_t width, uint32_t height) {
    RgbImage image{width, height, std::vector<std::array<double, 3>>(size_t(width) * height)};
    for (size_t i = 0; i < image.texels.size(); ++i)
      for (int c = 0; c < 3; ++c) image.texels[i][c] = half_to_float(float_to_half(lit[4 * i + c]));
    return image;
  }
};

// A night scene's range: dark surroundings, lit surfaces, neon a few hundred times brighter,
// at an odd size so every level rounds its size down and level 0 repeats the last column.
std::vector<float> night_scene(uint32_t width, uint32_t height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> exponent(-10.0f, 9.0f), unit(0.0f, 1.0f);
  std::vector<float> texels(size_t(width) * height * 4);
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const bool neon = unit(rng) < 0.01f;
    for (int c = 0; c < 3; ++c) texels[4 * i + c] = neon ? 400.0f * unit(rng) : std::exp2(exponent(rng));
    texels[4 * i + 3] = 1.0f;
  }
  return texels;
}

TEST_F(Bloom, EachLevelIsTheFilterOfTheLevelAboveToHalfAUlp) {
  const uint32_t width = 333, height = 197;
  const std::vector<float> lit = night_scene(width, height, 7);
  const ChainRun run = run_chain(lit, width, height);
  EXPECT_EQ(run.chain().desc.extent.width, 167u);
  EXPECT_EQ(run.chain().desc.extent.mips, kBloomLevels);
  for (uint32_t level = 0; level < kBloomLevels; ++level) EXPECT_TRUE(run.pass(level).runs);
  check_levels(run, as_image(lit, width, height), 1.5);
  // Alpha is 1 everywhere.
  const auto& bytes = *run.chain().bytes;
  for (size_t i = 0; i < bytes.size() / 8; ++i) {
    uint16_t a;
    std::memcpy(&a, bytes.data() + 8 * i + 6, 2);
    ASSERT_EQ(a, 0x3c00) << "texel " << i;
  }
}

TEST_F(Bloom, WidestBlurStaysWithinTheBound) {
  const uint32_t width = 200, height = 120;
  const std::vector<float> lit = night_scene(width, height, 11);
  std::map<std::string, ParamValues> params;
  for (uint32_t level = 0; level < kBloomLevels; ++level) params["bloom.level" + std::to_string(level)]["sigma"] = 2.6;
  check_levels(run_chain(lit, width, height, params), as_image(lit, width, height), 2.6);
}

// Stress: the largest half, +Inf, −Inf, negative values and NaN in one or all channels. NaN
// texels are black, the rest is clamped to [0, 65504]: the chain is finite and holds the bound.
TEST_F(Bloom, HugeInfiniteAndNanInputsGiveAFiniteChain) {
  const uint32_t width = 64, height = 48;
  std::vector<float> lit = night_scene(width, height, 3);
  const float specials[] = {65504.0f, INFINITY, -INFINITY, -3.0f, NAN, 60000.0f};
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      float* t = &lit[4 * (size_t(y) * width + x)];
      if (y < 16) {
        for (int c = 0; c < 3; ++c) t[c] = 65504.0f;  // a block at the top of the half range
      } else if ((x + y) % 5 == 0) {
        t[(x / 5) % 3] = specials[(x + 3 * y) % 6];
      }
    }
  const ChainRun run = run_chain(lit, width, height);
  check_levels(run, as_image(lit, width, height), 1.5);
  // The saturated block stays at the largest half, not Inf, through level 0.
  const RgbImage level0 = reference::decode_rgba16f(*run.chain().bytes, run.chain().desc.extent, 0);
  EXPECT_EQ(level0.at(16, 0)[0], 65504.0);
}

// Odd and tiny outputs: the chain has as many levels as its size allows; the passes beyond it
// are skipped and say why.
TEST_F(Bloom, TinyOutputsShortenTheChain) {
  for (auto [width, height, levels] : {std::tuple{1u, 1u, 1u}, {3u, 5u, 2u}, {7u, 2u, 3u}}) {
    const std::vector<float> lit = night_scene(width, height, width * 10 + height);
    const ChainRun run = run_chain(lit, width, height);
    ASSERT_EQ(run.chain().desc.extent.mips, levels) << width << "x" << height;
    for (uint32_t level = 0; level < kBloomLevels; ++level) {
      EXPECT_EQ(run.pass(level).runs, level < levels) << width << "x" << height << " level " << level;
      if (level >= levels) {
        EXPECT_EQ(run.pass(level).reason, "bloom.chain has " + std::to_string(levels) +
                                              (levels == 1 ? " level at " : " levels at ") + std::to_string(width) +
                                              "x" + std::to_string(height));
      }
    }
    check_levels(run, as_image(lit, width, height), 1.5);
  }
}

TEST_F(Bloom, OneSwitchSkipsEveryLevelAndTheChainIsCleared) {
  std::map<std::string, ParamValues> params;
  params["bloom"]["enabled"] = 0;
  const ChainRun run = run_chain(night_scene(64, 64, 1), 64, 64, params);
  for (uint32_t level = 0; level < kBloomLevels; ++level) {
    EXPECT_FALSE(run.pass(level).runs);
    EXPECT_EQ(run.pass(level).reason, "bloom disabled by settings (bloom.enabled=0)");
  }
  const auto& bytes = *run.chain().bytes;
  EXPECT_TRUE(std::all_of(bytes.begin(), bytes.end(), [](uint8_t b) { return b == 0; }));
}

TEST(BloomSwitch, TheGroupTakesEnabledOnly) {
  const std::vector<PassDecl> passes = frame_passes();
  ParamOverrides overrides;
  EXPECT_NO_THROW(parse_set(passes, "bloom.enabled=0", overrides));
  EXPECT_NO_THROW(parse_set(passes, "bloom.level3.sigma=2", overrides));
  EXPECT_THROW(parse_set(passes, "bloom.sigma=2", overrides), SetError);
  EXPECT_THROW(parse_set(passes, "bloom.enabled=0.5", overrides), SetError);
  EXPECT_THROW(parse_set(passes, "bloom.level3.enabled=0", overrides), SetError) << "a level's switch is the group's";
  EXPECT_EQ(overrides, (ParamOverrides{{"bloom", {{"enabled", 0}}}, {"bloom.level3", {{"sigma", 2}}}}));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
