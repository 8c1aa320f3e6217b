// depth.convert's half-resolution outputs against the CPU downsample of
// tests/reference/depth_half_reference.h (the nearest texel of each 2×2 footprint, clamped at odd
// edges, gives both the depth and the stencil).
//
// Bounds: stencil.half equals the reference exactly. depth.half is finite everywhere; where the
// exact metres reach 65504 it is exactly 65504; elsewhere |GPU − exact| ≤ ½ half-ULP of the
// exact value + 1 float ULP: the pass rounds depth.linear (within 1 float ULP of the exact value,
// tests/unit/depth_convert_test.cpp) to the nearest half. It also equals, bit for bit, the
// nearest half to the depth.linear it wrote at the chosen texel, so the two outputs agree.
//
// Inputs are crafted, so that every class and flag of passes/scene/scene.h occurs: device depths
// spread log-uniformly over [10⁻⁷, 1] (with znear = 0.05 the far ones exceed 65504 m), a quarter
// of them sky (0), and some footprints whose texels share one depth but not one stencil (the
// tie-break decides). No subnormal device depths: a device may flush them to 0 on sampling,
// which would change which texel is nearest.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/frame/gpu_types.h"
#include "tests/reference/depth_half_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr float kZnear = 0.05f;
constexpr double kSkyDepth = 1e6;

const uint8_t kTags[] = {stencil::plain,
                         stencil::road,
                         stencil::body,
                         stencil::face,
                         stencil::vehicle,
                         stencil::hair,
                         stencil::foliage,
                         stencil::body | stencil::moving,
                         stencil::vehicle | stencil::moving,
                         stencil::hair | stencil::moving,
                         stencil::foliage | stencil::moving};

struct Case {
  uint32_t width, height;
  bool all_sky;
};

struct Inputs {
  std::vector<float> device;
  std::vector<uint8_t> stencil;
};

Inputs crafted(uint32_t width, uint32_t height, bool all_sky) {
  std::mt19937 rng(width * 7919u + height);
  std::uniform_real_distribution<double> log_depth(-7.0, 0.0);
  Inputs in{std::vector<float>(size_t(width) * height), std::vector<uint8_t>(size_t(width) * height)};
  for (size_t i = 0; i < in.device.size(); ++i) {
    in.device[i] = all_sky || rng() % 4 == 0 ? 0.0f : float(std::pow(10.0, log_depth(rng)));
    in.stencil[i] = kTags[rng() % std::size(kTags)];
  }
  // Every fifth footprint: one depth for all of its texels, so only the tie-break picks.
  for (uint32_t y = 0; y + 1 < height; y += 2)
    for (uint32_t x = 0; x + 1 < width; x += 2)
      if ((x / 2 + y / 2) % 5 == 0) {
        const float shared = in.device[size_t(y) * width + x];
        in.device[size_t(y) * width + x + 1] = in.device[size_t(y + 1) * width + x] =
            in.device[size_t(y + 1) * width + x + 1] = shared;
      }
  return in;
}

IsolatedInput camera_input() {
  GpuView camera{};
  camera.projection_params = {kZnear, 1.0f, 1.0f, 0.0f};
  return record_input(camera);
}

double half_ulp(double x) { return std::ldexp(1.0, std::max(std::ilogb(x), -14) - 10); }
double float_ulp(double x) { return std::ldexp(1.0, std::ilogb(x) - 23); }

class DepthHalf : public GpuTest, public ::testing::WithParamInterface<Case> {};

TEST_P(DepthHalf, MatchesTheNearestTexelDownsample) {
  const auto [width, height, all_sky] = GetParam();
  const Inputs in = crafted(width, height, all_sky);
  const size_t pixels = in.device.size();
  // D32_SFLOAT_S8_UINT raw layout: the depth plane, then a byte of stencil per texel.
  std::vector<uint8_t> depth_bytes(pixels * 5);
  std::memcpy(depth_bytes.data(), in.device.data(), pixels * 4);
  std::memcpy(depth_bytes.data() + pixels * 4, in.stencil.data(), pixels);

  const IsolatedRun result =
      run(depth_convert_pass(),
          {{"frame.views", camera_input()},
           {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, width, height, depth_bytes)}},
          width, height, {{"sky_depth", kSkyDepth}});
  const reference::HalfDepthStencil expected =
      reference::half_depth_stencil(in.device, in.stencil, width, height, double(kZnear), kSkyDepth);
  const size_t half_texels = size_t(expected.width) * expected.height;
  EXPECT_EQ(result.output_descs.at("depth.half").extent.width, expected.width);
  EXPECT_EQ(result.output_descs.at("depth.half").extent.height, expected.height);
  const std::vector<uint8_t>& half_depth = *result.outputs.at("depth.half");
  const std::vector<uint8_t>& half_stencil = *result.outputs.at("stencil.half");
  const std::vector<uint8_t>& linear = *result.outputs.at("depth.linear");
  ASSERT_EQ(half_depth.size(), half_texels * 2);
  ASSERT_EQ(half_stencil.size(), half_texels);

  double worst_half_ulps = 0;
  size_t clamped = 0;
  for (size_t i = 0; i < half_texels; ++i) {
    ASSERT_EQ(half_stencil[i], expected.stencil[i]) << "half texel " << i;
    uint16_t bits;
    std::memcpy(&bits, half_depth.data() + 2 * i, 2);
    const double gpu = half_to_float(bits);
    ASSERT_TRUE(std::isfinite(gpu)) << "half texel " << i;
    float full;
    std::memcpy(&full, linear.data() + 4 * expected.source[i], 4);
    ASSERT_EQ(bits, float_to_half(std::min(full, 65504.0f))) << "half texel " << i << " vs depth.linear " << full;
    const double exact = expected.metres[i];
    if (exact == 65504.0) {
      ++clamped;
      ASSERT_EQ(gpu, 65504.0) << "half texel " << i;
      continue;
    }
    const double error = std::abs(gpu - exact);
    worst_half_ulps = std::max(worst_half_ulps, error / half_ulp(exact));
    ASSERT_LE(error, 0.5 * half_ulp(exact) + float_ulp(exact)) << "half texel " << i << ": exact " << exact;
  }
  if (all_sky) {
    EXPECT_EQ(clamped, half_texels);
  }
  std::printf("depth.half %ux%u%s: worst %.4f half ULP, %zu of %zu half texels at 65504\n", width, height,
              all_sky ? " (all sky)" : "", worst_half_ulps, clamped, half_texels);
}

INSTANTIATE_TEST_SUITE_P(, DepthHalf,
                         ::testing::Values(Case{1, 1, false}, Case{2, 2, false}, Case{7, 5, false},
                                           Case{1280, 720, false}, Case{1279, 719, false}, Case{1279, 719, true}),
                         [](const auto& info) {
                           return std::to_string(info.param.width) + "x" + std::to_string(info.param.height) +
                                  (info.param.all_sky ? "_all_sky" : "");
                         });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
