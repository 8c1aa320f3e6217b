// Diff metrics on inputs whose answers are known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <random>

#include "compare/decoded_image.h"
#include "compare/metrics.h"
#include "passes/depth/kinds.h"
#include "passes/gbuffer/kinds.h"
#include "tests/unit/image_record.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

TEST(DiffMetrics, FloatErrorsAreExact) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 4, 1);
  const auto a = floats({1.0f, 2.0f, 3.0f, 4.0f});
  const auto b = floats({1.0f, 2.5f, 3.0f, 2.0f});  // differences 0, 0.5, 0, 2
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_FALSE(c.identical);
  EXPECT_DOUBLE_EQ(c.max_abs, 2.0);
  // RMSE is the root of the MEAN of squares: sqrt((0.25 + 4) / 4).
  EXPECT_DOUBLE_EQ(c.rmse, std::sqrt(4.25 / 4.0));
  // Float peak is A's largest magnitude.
  EXPECT_NEAR(c.psnr, 20.0 * std::log10(4.0 / std::sqrt(4.25 / 4.0)), 1e-12);
  EXPECT_DOUBLE_EQ(c.over_threshold_share, 0.5);
  EXPECT_EQ(c.differing, 2u);
  EXPECT_EQ(c.metric, "float");
}

TEST(DiffMetrics, EveryHalfDecodesAsHalfToFloat) {
  // The diff decodes half images eight values at a time with bit arithmetic, not half_to_float.
  const FormatInfo format = *format_info(VK_FORMAT_R16_SFLOAT);
  std::vector<uint8_t> halves(65536 * 2);
  for (uint32_t h = 0; h < 65536; ++h) std::memcpy(&halves[2 * h], &h, 2);
  std::vector<float> values(65536);
  decode_values(format, 0, halves, values.data());
  for (uint32_t h = 0; h < 65536; ++h) {
    const float expected = half_to_float(uint16_t(h));
    if (std::isnan(expected))
      EXPECT_TRUE(std::isnan(values[h])) << std::hex << h;
    else
      EXPECT_EQ(std::bit_cast<uint32_t>(values[h]), std::bit_cast<uint32_t>(expected)) << std::hex << h;
  }
}

TEST(DiffMetrics, LargeHalfImagesMatchAPlainDoubleReckoning) {
  // 1500x3 RGBA: five blocks of the block-at-a-time comparison, the last partial; one block holds
  // a NaN and an infinity (the exact path), the others only finite values (the four-lane path).
  const uint32_t width = 1500, height = 3, values = width * height * 4;
  const ResourceRecord r = image_record(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-40.0f, 40.0f), change(-0.05f, 0.05f);
  std::vector<uint16_t> a(values), b(values);
  for (uint32_t i = 0; i < values; ++i) {
    a[i] = float_to_half(value(rng));
    // A quarter of the values stay equal; the rest move, some by more than the 1e-3 threshold.
    b[i] = i % 4 == 0 ? a[i] : float_to_half(half_to_float(a[i]) * (1.0f + change(rng)));
  }
  a[2500 * 4 + 1] = b[2500 * 4 + 1] = 0x7e00;  // NaN on both sides: agreement
  b[2600 * 4 + 2] = 0x7c00;                    // infinity in b only
  auto bytes = [](const std::vector<uint16_t>& h) {
    std::vector<uint8_t> out(h.size() * 2);
    std::memcpy(out.data(), h.data(), out.size());
    return out;
  };
  const ResourceComparison c = compare_resource(r, bytes(a), r, bytes(b));
  const auto contract = ComparisonContract::floats(1e-4, 2e-3, "test");
  const ContractCheck check = check_contract(contract, r, bytes(a), r, bytes(b));

  double max_abs = 0, squares = 0, peak = 1e-6, worst = 0;
  uint64_t counted = 0, differing = 0, over = 0;
  for (uint32_t t = 0; t < width * height; ++t) {
    bool texel_differs = false, texel_over = false;
    for (uint32_t ch = 0; ch < 4; ++ch) {
      const double x = half_to_float(a[t * 4 + ch]), y = half_to_float(b[t * 4 + ch]);
      if (std::isnan(x) && std::isnan(y)) continue;
      if (!std::isfinite(y)) {
        texel_differs = texel_over = true;
        worst = INFINITY;
        peak = std::max(peak, std::abs(x));
        ++counted;
        continue;
      }
      const double d = std::abs(x - y);
      peak = std::max(peak, std::abs(x));
      ++counted;
      squares += d * d;
      max_abs = std::max(max_abs, d);
      texel_differs |= d != 0;
      texel_over |= d > 1e-3 * std::max(1.0, std::abs(x));
      if (d != 0) worst = std::max(worst, d / (1e-4 + 2e-3 * std::abs(x)));
    }
    differing += texel_differs;
    over += texel_over;
  }
  EXPECT_TRUE(std::isinf(c.max_abs));  // the infinity
  EXPECT_EQ(c.nan_a, 1u);
  EXPECT_EQ(c.nan_b, 1u);
  EXPECT_EQ(c.inf_b, 1u);
  EXPECT_EQ(c.differing, differing);
  EXPECT_DOUBLE_EQ(c.over_threshold_share, double(over) / (width * height));
  EXPECT_NEAR(c.rmse, std::sqrt(squares / counted), 1e-12 * std::sqrt(squares / counted));
  EXPECT_NEAR(c.psnr, 20.0 * std::log10(peak / std::sqrt(squares / counted)), 1e-9);
  EXPECT_TRUE(std::isinf(check.worst));
  EXPECT_FALSE(check.holds);

  // Without the infinity, max abs and the contract's worst departure are finite and exact.
  b[2600 * 4 + 2] = a[2600 * 4 + 2];
  const ResourceComparison finite = compare_resource(r, bytes(a), r, bytes(b));
  const ContractCheck finite_check = check_contract(contract, r, bytes(a), r, bytes(b));
  double finite_max = 0, finite_worst = 0;
  for (uint32_t i = 0; i < values; ++i) {
    const double x = half_to_float(a[i]), y = half_to_float(b[i]);
    if (std::isnan(x)) continue;
    finite_max = std::max(finite_max, std::abs(x - y));
    if (x != y) finite_worst = std::max(finite_worst, std::abs(x - y) / (1e-4 + 2e-3 * std::abs(x)));
  }
  EXPECT_EQ(finite.max_abs, finite_max);
  EXPECT_EQ(finite_check.worst, finite_worst);
  EXPECT_EQ(finite_check.holds, finite_worst <= 1.0);
}

// The diff measures an output and its contract from one decoding (and, for floats, one pass):
// the figures must be those of the two separate measures, to the bit.
void expect_measured_as_apart(const ComparisonContract& contract, const ResourceRecord& r,
                              const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  const ResourcePair pair(r, a, r, b);
  const ResourceComparison apart = compare_resource(pair);
  const ContractCheck apart_check = check_contract(contract, pair, apart);
  const MeasuredResource together = measure_resource(contract, pair);
  const auto same = [](double x, double y) { return std::bit_cast<uint64_t>(x) == std::bit_cast<uint64_t>(y); };
  EXPECT_TRUE(same(together.comparison.max_abs, apart.max_abs)) << together.comparison.max_abs << " " << apart.max_abs;
  EXPECT_TRUE(same(together.comparison.rmse, apart.rmse));
  EXPECT_TRUE(same(together.comparison.psnr, apart.psnr));
  EXPECT_TRUE(same(together.comparison.over_threshold_share, apart.over_threshold_share));
  EXPECT_EQ(together.comparison.differing, apart.differing);
  EXPECT_EQ(together.comparison.nan_a, apart.nan_a);
  EXPECT_EQ(together.comparison.nan_b, apart.nan_b);
  EXPECT_EQ(together.comparison.inf_a, apart.inf_a);
  EXPECT_EQ(together.comparison.inf_b, apart.inf_b);
  EXPECT_TRUE(same(together.contract.worst, apart_check.worst)) << together.contract.worst << " " << apart_check.worst;
  EXPECT_EQ(together.contract.holds, apart_check.holds);
  EXPECT_TRUE(same(together.contract.bound, apart_check.bound));
  EXPECT_EQ(together.contract.measure, apart_check.measure);
}

TEST(DiffMetrics, MeasuredTogetherAsApart) {
  // Float, codes and depth contracts over blocks of finite values (the four-lane path) and over
  // blocks holding NaN or an infinity (the exact path).
  const uint32_t width = 1500, height = 3;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(-40.0f, 40.0f), change(-0.01f, 0.01f);
  const ResourceRecord half = image_record(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height);
  std::vector<uint16_t> a(width * height * 4), b(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = float_to_half(value(rng));
    b[i] = i % 3 == 0 ? a[i] : float_to_half(half_to_float(a[i]) * (1.0f + change(rng)));
  }
  auto bytes = [](const auto& values) {
    std::vector<uint8_t> out(values.size() * sizeof(values[0]));
    std::memcpy(out.data(), values.data(), out.size());
    return out;
  };
  for (const ComparisonContract& contract :
       {ComparisonContract::floats(1e-4, 2e-3, "test"), ComparisonContract::floats(0.0, 0.0, "test")}) {
    expect_measured_as_apart(contract, half, bytes(a), bytes(b));
    std::vector<uint16_t> with_nan = b;
    with_nan[2500 * 4 + 1] = 0x7e00;
    with_nan[10] = 0x7c00;
    expect_measured_as_apart(contract, half, bytes(a), bytes(with_nan));
  }

  const ResourceRecord unorm = image_record(VK_FORMAT_R16_UNORM, kinds::lookup_table, width, height);
  std::vector<uint16_t> codes_a(width * height), codes_b(codes_a.size());
  for (size_t i = 0; i < codes_a.size(); ++i) {
    codes_a[i] = uint16_t(rng());
    codes_b[i] = uint16_t(codes_a[i] + (i % 5 == 0 ? rng() % 3 : 0));
  }
  expect_measured_as_apart(ComparisonContract::codes(1, "test"), unorm, bytes(codes_a), bytes(codes_b));

  const ResourceRecord depth = image_record(VK_FORMAT_R32_SFLOAT, kinds::linear_depth, width, height);
  std::vector<float> near(width * height), far(near.size());
  for (size_t i = 0; i < near.size(); ++i) {
    near[i] = 0.5f + float(i % 97);
    far[i] = i % 7 == 0 ? near[i] * 1.0004f : near[i];
  }
  expect_measured_as_apart(ComparisonContract::depth(5e-4, "test"), depth, bytes(near), bytes(far));
  far[17] = NAN;
  expect_measured_as_apart(ComparisonContract::depth(5e-4, "test"), depth, bytes(near), bytes(far));
}

TEST(DiffMetrics, IdenticalInputsHaveInfinitePsnr) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 2, 1);
  const auto a = floats({1.0f, -7.0f});
  const ResourceComparison c = compare_resource(r, a, r, a);
  EXPECT_TRUE(c.identical);
  EXPECT_EQ(c.max_abs, 0.0);
  EXPECT_TRUE(std::isinf(c.psnr));
}

TEST(DiffMetrics, NanAndInfAreCountedAndNanInBothPlacesAgrees) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 4, 1);
  const auto a = floats({NAN, 1.0f, INFINITY, 2.0f});
  const auto b = floats({NAN, NAN, INFINITY, 2.0f});
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_EQ(c.nan_a, 1u);
  EXPECT_EQ(c.nan_b, 2u);
  EXPECT_EQ(c.inf_a, 1u);
  EXPECT_EQ(c.inf_b, 1u);
  EXPECT_EQ(c.differing, 1u);  // only texel 1: NaN against NaN and Inf against Inf agree
  EXPECT_TRUE(std::isinf(c.max_abs));
}

TEST(DiffMetrics, UnormOneCodeOff) {
  const ResourceRecord r = image_record(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, 2, 1);
  const std::vector<uint8_t> a = {10, 20, 30, 255, 0, 0, 0, 0};
  std::vector<uint8_t> b = a;
  b[1] = 21;
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_NEAR(c.max_abs, 1.0 / 255.0, 1e-7);
  EXPECT_NEAR(c.rmse, std::sqrt((1.0 / 255.0) * (1.0 / 255.0) / 8.0), 1e-9);
  EXPECT_EQ(c.over_threshold_share, 0.0);  // one code is within the 8-bit threshold
  EXPECT_EQ(c.differing, 1u);
}

TEST(DiffMetrics, NormalsReportTheAngleBetweenThem) {
  const ResourceRecord r = image_record(VK_FORMAT_R32G32B32A32_SFLOAT, kinds::normal, 1, 1);
  // 0.5n+0.5 encoding: +Z, and +Z rotated by 10 degrees about X.
  const double angle = 10.0 * M_PI / 180.0;
  const auto a = floats({0.5f, 0.5f, 1.0f, 0.0f});
  const auto b = floats({0.5f, float(0.5 + 0.5 * std::sin(angle)), float(0.5 + 0.5 * std::cos(angle)), 0.0f});
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_EQ(c.metric, "angle");
  EXPECT_NEAR(c.angular_max_deg, 10.0, 1e-4);
  EXPECT_NEAR(c.angular_mean_deg, 10.0, 1e-4);
}

TEST(DiffMetrics, StencilIsComparedExactly) {
  const ResourceRecord r = image_record(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, 2, 1);
  std::vector<uint8_t> a(2 * 4 + 2, 0), b;
  const float depth[2] = {0.5f, 0.25f};
  std::memcpy(a.data(), depth, 8);
  a[8] = 0x08;
  a[9] = 0x40;
  b = a;
  b[9] = 0x42;  // moving vehicle instead of vehicle
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_EQ(c.metric, "depth + stencil");
  EXPECT_EQ(c.differing, 1u);
  EXPECT_DOUBLE_EQ(c.max_abs, 2.0);
}

TEST(DiffMetrics, BuffersCompareWordsAndSizeMismatchIsNotComparable) {
  ResourceRecord r;
  r.is_buffer = true;
  r.buffer_size = 8;
  const auto a = floats({1.0f, 2.0f}), b = floats({1.0f, 2.25f});
  const ResourceComparison c = compare_resource(r, a, r, b);
  EXPECT_EQ(c.differing, 1u);
  EXPECT_DOUBLE_EQ(c.max_abs, 0.25);
  ResourceRecord shorter = r;
  shorter.buffer_size = 4;
  const auto d = floats({1.0f});
  EXPECT_FALSE(compare_resource(r, a, shorter, d).comparable);
}

// Comparison contracts: each kind holds exactly up to its bound and fails just past it.
TEST(Contract, FloatValuesHoldUpToAbsolutePlusRelative) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 2, 1);
  const auto contract = ComparisonContract::floats(0.01, 0.1, "test");
  const auto a = floats({1.0f, 100.0f});
  // Allowed: 0.01 + 0.1·1 = 0.11 and 0.01 + 0.1·100 = 10.01.
  EXPECT_TRUE(check_contract(contract, r, a, r, floats({1.1f, 110.0f})).holds);
  EXPECT_FALSE(check_contract(contract, r, a, r, floats({1.12f, 100.0f})).holds);
  EXPECT_FALSE(check_contract(contract, r, a, r, floats({1.0f, 110.02f})).holds);
  const ContractCheck nan = check_contract(contract, r, a, r, floats({NAN, 100.0f}));
  EXPECT_FALSE(nan.holds);
  EXPECT_TRUE(std::isinf(nan.worst));
}

TEST(Contract, ExactMeansEveryByte) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 2, 1);
  const ComparisonContract exact;
  EXPECT_TRUE(check_contract(exact, r, floats({1.0f, 2.0f}), r, floats({1.0f, 2.0f})).holds);
  const ContractCheck one =
      check_contract(exact, r, floats({1.0f, 2.0f}), r, floats({1.0f, std::nextafter(2.0f, 3.0f)}));
  EXPECT_FALSE(one.holds);
  EXPECT_EQ(one.worst, 1.0);
}

TEST(Contract, UnormCodesCountStepsOfTheFormat) {
  const ResourceRecord r = image_record(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, 1, 1);
  const auto contract = ComparisonContract::codes(1, "test");
  const std::vector<uint8_t> a = {10, 20, 30, 255};
  EXPECT_TRUE(check_contract(contract, r, a, r, std::vector<uint8_t>{11, 19, 30, 255}).holds);
  const ContractCheck two = check_contract(contract, r, a, r, std::vector<uint8_t>{12, 20, 30, 255});
  EXPECT_FALSE(two.holds);
  EXPECT_NEAR(two.worst, 2.0, 1e-9);
}

TEST(Contract, SrgbCodesAreCountedBeforeDecoding) {
  const ResourceRecord r = image_record(VK_FORMAT_R8G8B8A8_SRGB, kinds::colour, 1, 1);
  const std::vector<uint8_t> a = {200, 20, 3, 255};
  EXPECT_TRUE(
      check_contract(ComparisonContract::codes(1, "test"), r, a, r, std::vector<uint8_t>{201, 19, 4, 255}).holds);
  EXPECT_FALSE(
      check_contract(ComparisonContract::codes(1, "test"), r, a, r, std::vector<uint8_t>{200, 22, 3, 255}).holds);
}

TEST(Contract, ByteCodesLargestStepWhereverItIs) {
  // 9x5 RGBA8: 180 bytes, read 32 at a time and the last 20 one by one. Each step is found alone,
  // wherever it lies, in either direction, and the largest of several wins.
  const ResourceRecord r = image_record(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, 9, 5);
  const auto contract = ComparisonContract::codes(1, "test");
  std::vector<uint8_t> a(180);
  for (size_t i = 0; i < a.size(); ++i) a[i] = uint8_t(i * 37 % 200 + 20);
  for (size_t at : {size_t(0), size_t(31), size_t(32), size_t(159), size_t(160), size_t(179)})
    for (int step : {-17, 3, 235}) {
      std::vector<uint8_t> b = a;
      b[at] = uint8_t(std::clamp(int(a[at]) + step, 0, 255));
      EXPECT_EQ(check_contract(contract, r, a, r, b).worst, std::abs(int(b[at]) - int(a[at]))) << at << " " << step;
    }
  std::vector<uint8_t> b = a;
  b[5] = uint8_t(a[5] + 2);
  b[170] = uint8_t(a[170] - 9);
  b[64] = uint8_t(a[64] + 4);
  EXPECT_EQ(check_contract(contract, r, a, r, b).worst, 9.0);
  EXPECT_EQ(check_contract(contract, r, a, r, a).worst, 0.0);
}

TEST(Contract, AnglesOfNormals) {
  const ResourceRecord r = image_record(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal, 1, 1);
  auto word = [](int x, int y, int z) {
    const uint32_t w = uint32_t(x) | uint32_t(y) << 10 | uint32_t(z) << 20;
    std::vector<uint8_t> bytes(4);
    std::memcpy(bytes.data(), &w, 4);
    return bytes;
  };
  // +Z against a normal tilted by one code in x: atan(2/1023 / 1) ≈ 0.112°.
  const auto a = word(512, 512, 1023), b = word(513, 512, 1023);
  EXPECT_TRUE(check_contract(ComparisonContract::degrees(0.2, "test"), r, a, r, b).holds);
  EXPECT_FALSE(check_contract(ComparisonContract::degrees(0.05, "test"), r, a, r, b).holds);
}

TEST(Contract, LinearDepthIsRelativeAndStencilExact) {
  const ResourceRecord r = image_record(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, 1, 1);
  auto texel = [](float depth, uint8_t stencil) {
    std::vector<uint8_t> bytes(5);
    std::memcpy(bytes.data(), &depth, 4);
    bytes[4] = stencil;
    return bytes;
  };
  const auto contract = ComparisonContract::depth(1e-3, "test");
  EXPECT_TRUE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5004f, 8)).holds);
  EXPECT_FALSE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5006f, 8)).holds);
  EXPECT_FALSE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5f, 0x0A)).holds);
}

TEST(Contract, SetsIgnoreOrderButNotContent) {
  ResourceRecord r;
  r.is_buffer = true;
  r.buffer_size = 12;
  auto words = [](uint32_t a, uint32_t b, uint32_t c) {
    std::vector<uint8_t> bytes(12);
    const uint32_t w[3] = {a, b, c};
    std::memcpy(bytes.data(), w, 12);
    return bytes;
  };
  const auto contract = ComparisonContract::unordered("test");
  EXPECT_TRUE(contract.order_dependent);
  EXPECT_TRUE(check_contract(contract, r, words(1, 2, 3), r, words(3, 1, 2)).holds);
  EXPECT_FALSE(check_contract(contract, r, words(1, 2, 3), r, words(3, 1, 1)).holds);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
