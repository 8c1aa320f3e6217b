// normals.half against a CPU downsample: each half texel of normals.half and motion.half is, bit
// for bit, the full texel of normals.packed and gbuffer.motion that
// tests/reference/depth_half_reference.h picks for depth.half (the footprint's nearest texel,
// the first in row order among equal depths, cut at odd edges). Inputs are crafted: random
// normal codes and roughness, motions over the whole half range (±65504, subnormals, zero of
// both signs), device depths log-uniform over [10⁻⁷, 1] with a quarter sky and every fifth
// footprint one depth throughout, so the tie-break decides. Sizes: 1×1, 7×5 (odd edges), 640×360
// and 1279×719.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/depth/kinds.h"
#include "passes/gbuffer/kinds.h"
#include "passes/normals/kinds.h"
#include "passes/normals/stage.h"
#include "tests/reference/depth_half_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

struct Size {
  uint32_t width, height;
};

class NormalsHalf : public GpuTest, public ::testing::WithParamInterface<Size> {};

TEST_P(NormalsHalf, CopiesTheTexelDepthHalfTakes) {
  const auto [width, height] = GetParam();
  const size_t pixels = size_t(width) * height;
  std::mt19937 rng(width * 31u + height);
  std::uniform_real_distribution<double> log_depth(-7.0, 0.0);
  std::vector<float> device(pixels);
  for (float& d : device) d = rng() % 4 == 0 ? 0.0f : float(std::pow(10.0, log_depth(rng)));
  for (uint32_t y = 0; y + 1 < height; y += 2)
    for (uint32_t x = 0; x + 1 < width; x += 2)
      if ((x / 2 + y / 2) % 5 == 0)
        device[size_t(y) * width + x + 1] = device[size_t(y + 1) * width + x] = device[size_t(y + 1) * width + x + 1] =
            device[size_t(y) * width + x];
  std::vector<uint8_t> normals(pixels * 4), motion(pixels * 4);
  for (uint8_t& code : normals) code = uint8_t(rng());
  const uint16_t special[] = {0x0000, 0x8000, 0x0001, 0x83ff, 0x7bff, 0xfbff, 0x3c00};
  for (size_t i = 0; i < pixels * 2; ++i) {
    uint16_t h = i % 9 == 0 ? special[rng() % std::size(special)] : uint16_t(rng());
    if ((h & 0x7c00) == 0x7c00) h &= 0xfbff;  // finite: no Inf or NaN
    std::memcpy(motion.data() + i * 2, &h, 2);
  }
  // D32_SFLOAT_S8_UINT raw layout: the depth plane, then a byte of stencil per texel.
  std::vector<uint8_t> depth_bytes(pixels * 5, 0);
  std::memcpy(depth_bytes.data(), device.data(), pixels * 4);

  const IsolatedRun result =
      run(normals_half_pass(),
          {{"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, width, height, depth_bytes)},
           {"normals.packed", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::packed_normal, width, height, normals)},
           {"gbuffer.motion", image(VK_FORMAT_R16G16_SFLOAT, kinds::motion, width, height, motion)}},
          width, height);
  const reference::HalfDepthStencil expected =
      reference::half_depth_stencil(device, std::vector<uint8_t>(pixels, 0), width, height, 0.05, 1e6);
  EXPECT_EQ(result.output_descs.at("normals.half").extent.width, expected.width);
  EXPECT_EQ(result.output_descs.at("motion.half").extent.height, expected.height);
  const std::vector<uint8_t>& half_normals = *result.outputs.at("normals.half");
  const std::vector<uint8_t>& half_motion = *result.outputs.at("motion.half");
  ASSERT_EQ(half_normals.size(), expected.source.size() * 4);
  ASSERT_EQ(half_motion.size(), expected.source.size() * 4);
  size_t wrong_normals = 0, wrong_motion = 0;
  for (size_t i = 0; i < expected.source.size(); ++i) {
    const size_t s = expected.source[i];
    wrong_normals += std::memcmp(half_normals.data() + i * 4, normals.data() + s * 4, 4) != 0;
    wrong_motion += std::memcmp(half_motion.data() + i * 4, motion.data() + s * 4, 4) != 0;
  }
  EXPECT_EQ(wrong_normals, 0u);
  EXPECT_EQ(wrong_motion, 0u);
}

INSTANTIATE_TEST_SUITE_P(, NormalsHalf, ::testing::Values(Size{1, 1}, Size{7, 5}, Size{640, 360}, Size{1279, 719}),
                         [](const auto& info) {
                           return std::to_string(info.param.width) + "x" + std::to_string(info.param.height);
                         });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
