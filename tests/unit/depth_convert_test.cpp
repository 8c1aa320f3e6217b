// depth.convert against a double-precision reference: linear depth = znear / device depth
// (reversed-Z, infinite far plane), clamped at sky_depth, and exactly sky_depth where the device
// depth is 0. Every device depth is a D32 float as the GPU samples it; znear is the float in
// frame.constants.projection_params.x and sky_depth the float the pass pushes.
//
// Bound: |GPU − reference| ≤ 1 float ULP of the reference. One correctly rounded division is
// half an ULP; Vulkan allows 2.5 ULP for a division, so an implementation computing
// znear · (1 / device) (two roundings) still passes, a cruder one does not. Sky pixels and
// every clamped pixel must be exactly sky_depth, never Inf.
//
// The sweep takes 1024 device depths from each binade below 1 (edges of the mantissa included,
// the largest float below 1 among them), every binade of subnormals, 0 and 1. The (znear,
// sky_depth) pairs all satisfy znear / 2⁻¹²⁶ ≥ sky_depth, so a subnormal device depth must give
// sky_depth whether or not the implementation flushes it to zero on sampling (Vulkan allows
// either); with znear = 10 and sky_depth = 3·10³⁸ the float quotient itself overflows to Inf
// for every device depth below about 2.9·10⁻³⁸.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/frame/gpu_types.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

float from_bits(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

// Device depths in [0, 1]: 1024 per float exponent field 0..126, then 0 and 1.
std::vector<float> device_depth_sweep() {
  std::mt19937 rng(20240611);
  std::vector<float> depths;
  for (uint32_t exponent = 0; exponent <= 126; ++exponent)
    for (uint32_t k = 0; k < 1024; ++k) {
      uint32_t mantissa = k == 0 ? 0 : k == 1 ? 1 : k == 2 ? 0x7fffff : rng() & 0x7fffff;
      if (exponent == 0 && mantissa == 0) mantissa = 1;
      depths.push_back(from_bits(exponent << 23 | mantissa));
    }
  for (int k = 0; k < 64; ++k) depths.push_back(0.0f);
  depths.push_back(1.0f);
  return depths;
}

// Distance between adjacent floats around a positive normal value.
double float_ulp(double x) { return std::ldexp(1.0, std::ilogb(x) - 23); }

struct Case {
  float znear, sky_depth;
};

class DepthConvert : public GpuTest, public ::testing::WithParamInterface<Case> {};

TEST_P(DepthConvert, MatchesTheDoubleReferenceWithinOneUlp) {
  const auto [znear, sky_depth] = GetParam();
  const std::vector<float> depths = device_depth_sweep();
  const uint32_t width = 512, height = uint32_t((depths.size() + width - 1) / width);
  const size_t pixels = size_t(width) * height;
  std::vector<float> device(pixels, 0.0f);
  std::copy(depths.begin(), depths.end(), device.begin());
  // D32_SFLOAT_S8_UINT raw layout: the depth plane, then a byte of stencil per texel.
  std::vector<uint8_t> depth_bytes(pixels * 5, 0);
  std::memcpy(depth_bytes.data(), device.data(), pixels * 4);

  GpuView camera{};
  camera.projection_params = {znear, 1.0f, 1.0f, 0.0f};

  const IsolatedRun result =
      run(depth_convert_pass(),
          {{"frame.views", record_input(camera)},
           {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, width, height, depth_bytes)}},
          width, height, {{"sky_depth", sky_depth}});
  const std::vector<uint8_t>& out = *result.outputs.at("depth.linear");
  ASSERT_EQ(out.size(), pixels * 4);

  double worst_ulps = 0, worst_relative = 0;
  size_t clamped = 0;
  for (size_t i = 0; i < pixels; ++i) {
    float gpu;
    std::memcpy(&gpu, out.data() + 4 * i, 4);
    const double d = device[i];
    const double expected = d > 0 ? std::min(double(znear) / d, double(sky_depth)) : double(sky_depth);
    if (expected == double(sky_depth)) {
      ++clamped;
      ASSERT_EQ(gpu, sky_depth) << "device depth " << d << " (pixel " << i << ")";
      continue;
    }
    ASSERT_TRUE(std::isfinite(gpu)) << "device depth " << d;
    const double error = std::abs(double(gpu) - expected);
    const double ulps = error / float_ulp(expected);
    worst_ulps = std::max(worst_ulps, ulps);
    worst_relative = std::max(worst_relative, error / expected);
    ASSERT_LE(ulps, 1.0) << "device depth " << d << ": got " << gpu << ", expected " << expected;
  }
  EXPECT_GT(clamped, 64u);
  std::printf("depth.convert znear %g sky_depth %g: worst %.4f ULP, %.4g relative; %zu pixels at sky_depth\n",
              double(znear), double(sky_depth), worst_ulps, worst_relative, clamped);
}

INSTANTIATE_TEST_SUITE_P(, DepthConvert,
                         ::testing::Values(Case{0.05f, 1e6f}, Case{1e-3f, 1e6f}, Case{0.1f, 1e30f}, Case{1.0f, 1e6f},
                                           Case{10.0f, 3e38f}));

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
