// depth.pyramid against a CPU min/max over every footprint (exact), and its conservativeness
// against the full-resolution region each texel stands for, odd sizes included.
#include <cstring>
#include <random>

#include "passes/depth/stage.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

struct Level {
  uint32_t width, height;
  std::vector<float> min, max;
};

// The reference: the same footprint rule as the shader, computed independently on the CPU.
std::vector<Level> cpu_pyramid(const std::vector<float>& depth, uint32_t width, uint32_t height) {
  std::vector<Level> levels;
  const uint32_t base_w = (width + 1) / 2, base_h = (height + 1) / 2;
  const uint32_t mips = full_mip_count(base_w, base_h);
  uint32_t src_w = width, src_h = height;
  std::vector<float> src_min = depth, src_max = depth;
  for (uint32_t m = 0; m < mips; ++m) {
    Level level{mip_size(base_w, m), mip_size(base_h, m), {}, {}};
    for (uint32_t y = 0; y < level.height; ++y)
      for (uint32_t x = 0; x < level.width; ++x) {
        const uint32_t x1 = x == level.width - 1 ? src_w - 1 : std::min(2 * x + 1, src_w - 1);
        const uint32_t y1 = y == level.height - 1 ? src_h - 1 : std::min(2 * y + 1, src_h - 1);
        float lo = INFINITY, hi = -INFINITY;
        for (uint32_t sy = 2 * y; sy <= y1; ++sy)
          for (uint32_t sx = 2 * x; sx <= x1; ++sx) {
            lo = std::min(lo, src_min[sy * src_w + sx]);
            hi = std::max(hi, src_max[sy * src_w + sx]);
          }
        level.min.push_back(lo);
        level.max.push_back(hi);
      }
    src_min = level.min;
    src_max = level.max;
    src_w = level.width;
    src_h = level.height;
    levels.push_back(std::move(level));
  }
  return levels;
}

class DepthPyramid : public GpuTest, public ::testing::WithParamInterface<std::pair<uint32_t, uint32_t>> {};

TEST_P(DepthPyramid, MatchesTheCpuMinMaxExactlyAndIsConservative) {
  const auto [width, height] = GetParam();
  std::mt19937 rng(width * 7919 + height);
  std::vector<float> depth(size_t(width) * height);
  // Metres across a city: near surfaces, far ones, and the sky value.
  for (float& d : depth) {
    const uint32_t r = rng();
    d = r % 17 == 0 ? 1e6f : 0.05f + float(r % 1000000) * 0.004f;
  }
  std::vector<uint8_t> bytes(depth.size() * 4);
  std::memcpy(bytes.data(), depth.data(), bytes.size());
  const IsolatedRun result =
      run(depth_pyramid_pass(),
          {{"depth.linear", image(VK_FORMAT_R32_SFLOAT, kinds::linear_depth, width, height, bytes)}}, width, height);
  const ResourceDesc& desc = result.output_descs.at("depth.pyramid");
  const std::vector<uint8_t>& out = *result.outputs.at("depth.pyramid");
  const std::vector<Level> expected = cpu_pyramid(depth, width, height);
  ASSERT_EQ(desc.extent.mips, expected.size());
  const FormatInfo format = *format_info(VK_FORMAT_R32G32_SFLOAT);
  for (uint32_t m = 0; m < expected.size(); ++m) {
    const uint64_t offset = raw_subresource_offset(format, desc.extent, 0, m, 0);
    const Level& level = expected[m];
    // Each texel of level m stands for a block of 2^(m+1) full-resolution texels (more at the
    // odd edges); every depth inside the block must lie within [min, max].
    const uint32_t block = 2u << m;
    for (uint32_t y = 0; y < level.height; ++y)
      for (uint32_t x = 0; x < level.width; ++x) {
        float gpu[2];
        std::memcpy(gpu, out.data() + offset + (size_t(y) * level.width + x) * 8, 8);
        const size_t i = size_t(y) * level.width + x;
        ASSERT_EQ(gpu[0], level.min[i]) << "mip " << m << " texel " << x << "," << y;
        ASSERT_EQ(gpu[1], level.max[i]) << "mip " << m << " texel " << x << "," << y;
        const uint32_t x_end = x == level.width - 1 ? width : std::min(width, (x + 1) * block);
        const uint32_t y_end = y == level.height - 1 ? height : std::min(height, (y + 1) * block);
        for (uint32_t sy = y * block; sy < y_end; ++sy)
          for (uint32_t sx = x * block; sx < x_end; ++sx) {
            ASSERT_LE(gpu[0], depth[sy * width + sx]);
            ASSERT_GE(gpu[1], depth[sy * width + sx]);
          }
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, DepthPyramid,
                         ::testing::Values(std::make_pair(1u, 1u), std::make_pair(2u, 1u), std::make_pair(3u, 3u),
                                           std::make_pair(37u, 23u), std::make_pair(129u, 65u),
                                           std::make_pair(320u, 180u), std::make_pair(1279u, 719u)));

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
