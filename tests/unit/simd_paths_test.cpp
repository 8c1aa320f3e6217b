// Every SIMD path this CPU has (compare/simd.h) against the generic path, bit for bit: each loop of
// compare/simd_kernels.h on the same inputs, random values mixed with the edge cases (NaN, ±infinity,
// ±0, subnormals, the extreme normals, every half), at lengths that end in each loop's vector part
// and in its tail.
//
// Where a loop's inputs hold NaNs, its NaNs are held to being NaN, not to their bits: IEEE 754
// leaves open which NaN an operation on two NaNs returns (x86 returns its first operand's), so a
// commutative operation returns the NaN of whichever operand the compiler put first, which differs
// between paths. A NaN made inside a loop is x86's default NaN on every path, so from finite inputs
// (including those that overflow to infinity and make NaNs) the paths agree to the bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "compare/simd_kernels.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

using simd::Path;

// Lengths around every width the loops step by (4, 8, 16, 32 and 64 values) and their tails.
const std::vector<uint32_t> kLengths = {0,  1,  3,  4,  5,  7,  8,  9,   15,  16,  17,
                                        31, 32, 33, 63, 64, 65, 71, 127, 128, 200, 1027};

std::string path_names(const std::vector<Path>& paths) {
  std::string names;
  for (Path path : paths) names += std::string(names.empty() ? "" : " ") + simd::path_name(path);
  return names;
}

// The paths to hold to the generic one: every other path the CPU has. A CPU with the generic path
// alone has nothing to compare, and the test says so by skipping rather than passing.
class SimdPaths : public testing::Test {
 protected:
  void SetUp() override {
    const std::vector<Path> supported = simd::supported_paths();
    RecordProperty("simd_paths", path_names(supported));
    std::cout << "SIMD paths this CPU has: " << path_names(supported) << "\n";
    for (Path path : supported)
      if (path != Path::generic) wider_.push_back(path);
    if (wider_.empty()) GTEST_SKIP() << "this CPU has the generic path only: no other path to compare with it";
  }

  std::vector<Path> wider_;
};

// Random floats in [−scale, scale] with, one in two, an edge case: quiet and signalling NaNs with
// payloads, ±infinity, ±0, subnormals, the extreme normals, any bit pattern.
std::vector<float> mixed_floats(size_t n, uint32_t seed, float scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(-scale, scale);
  std::vector<float> values(n);
  for (float& v : values) {
    const uint32_t bits = rng(), sign = bits & 0x80000000u;
    switch (rng() % 16) {
      case 0:
        v = std::bit_cast<float>(sign | 0x7fc00000u | (bits & 0x3fffffu));  // quiet NaN
        break;
      case 1:
        v = std::bit_cast<float>(sign | 0x7f800000u | (bits & 0x3fffffu) | 1u);  // signalling NaN
        break;
      case 2:
        v = std::bit_cast<float>(sign | 0x7f800000u);  // ±infinity
        break;
      case 3:
        v = std::bit_cast<float>(sign);  // ±0
        break;
      case 4:
        v = std::bit_cast<float>(sign | (bits & 0x7fffffu) | 1u);  // subnormal
        break;
      case 5:
        v = std::bit_cast<float>(sign | (bits & 1 ? 0x00800000u : 0x7f7fffffu));  // extreme normals
        break;
      case 6:
        v = std::bit_cast<float>(bits);
        break;
      default:
        v = uniform(rng);
    }
  }
  return values;
}

// Finite values only: uniform in [−scale, scale], with subnormals, ±0 and the largest normals.
std::vector<float> finite_floats(size_t n, uint32_t seed, float scale) {
  std::vector<float> values = mixed_floats(n, seed, scale);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<float> uniform(-scale, scale);
  for (float& v : values)
    if (!std::isfinite(v)) v = uniform(rng);
  return values;
}

enum class Nans { same_bits, any_nan };

::testing::AssertionResult same_bits(const std::vector<float>& expected, const std::vector<float>& actual,
                                     Nans nans = Nans::same_bits) {
  if (expected.size() != actual.size()) return ::testing::AssertionFailure() << "sizes differ";
  for (size_t i = 0; i < expected.size(); ++i) {
    const uint32_t expected_bits = std::bit_cast<uint32_t>(expected[i]),
                   actual_bits = std::bit_cast<uint32_t>(actual[i]);
    if (expected_bits == actual_bits || (nans == Nans::any_nan && std::isnan(expected[i]) && std::isnan(actual[i])))
      continue;
    return ::testing::AssertionFailure() << "first difference at " << i << ": generic " << std::hexfloat << expected[i]
                                         << ", this path " << actual[i] << std::hex << " (bits 0x" << expected_bits
                                         << " vs 0x" << actual_bits << ")";
  }
  return ::testing::AssertionSuccess();
}

bool same_bits(double x, double y) { return std::bit_cast<uint64_t>(x) == std::bit_cast<uint64_t>(y); }

TEST_F(SimdPaths, HalvesToFloatsOfEveryHalf) {
  const auto generic = decode_kernels::compiled_for(Path::generic).halves_to_floats;
  // Every half: each exponent with every mantissa, subnormals, infinities and NaNs of both signs.
  std::vector<uint8_t> halves(2 * 65536);
  for (uint32_t h = 0; h < 65536; ++h) {
    halves[2 * h] = uint8_t(h);
    halves[2 * h + 1] = uint8_t(h >> 8);
  }
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto convert = decode_kernels::compiled_for(path).halves_to_floats;
    ASSERT_NE(convert, generic);
    std::vector<float> expected(65536), actual(65536);
    generic(halves.data(), expected.data(), 65536);
    convert(halves.data(), actual.data(), 65536);
    EXPECT_TRUE(same_bits(expected, actual));
    // Every length's tail, from an odd start too.
    for (uint32_t start : {0u, 1u, 0x7bf0u, 0xfbfbu})
      for (uint32_t n : kLengths) {
        const uint32_t count = std::min(n, 65536 - start);
        std::vector<float> tail_expected(count + 1, -1.0f), tail_actual(count + 1, -1.0f);
        generic(halves.data() + 2 * start, tail_expected.data(), count);
        convert(halves.data() + 2 * start, tail_actual.data(), count);
        EXPECT_TRUE(same_bits(tail_expected, tail_actual)) << "start " << start << ", " << count << " halves";
      }
  }
}

TEST_F(SimdPaths, Magnitudes) {
  const auto generic = flip_kernels::compiled_for(Path::generic).magnitudes;
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto magnitudes = flip_kernels::compiled_for(path).magnitudes;
    ASSERT_NE(magnitudes, generic);
    for (bool finite : {true, false})
      for (uint32_t n : kLengths) {
        const auto floats = finite ? finite_floats : mixed_floats;
        const std::vector<float> u = floats(n, n, 4.0f), v = floats(n, n + 1000, 4.0f);
        std::vector<float> expected(n + 1, -1.0f), actual(n + 1, -1.0f);
        generic(u.data(), v.data(), expected.data(), n);
        magnitudes(u.data(), v.data(), actual.data(), n);
        EXPECT_TRUE(same_bits(expected, actual, finite ? Nans::same_bits : Nans::any_nan))
            << n << " values, finite " << finite;
      }
  }
}

TEST_F(SimdPaths, WeightedSum) {
  const auto generic = flip_kernels::compiled_for(Path::generic).weighted_sum;
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto weighted_sum = flip_kernels::compiled_for(path).weighted_sum;
    ASSERT_NE(weighted_sum, generic);
    for (bool finite : {true, false})
      for (size_t taps : {1u, 5u, 13u})
        for (bool zero_sum : {false, true})
          for (bool add : {false, true})
            for (uint32_t n : kLengths) {
              const uint32_t seed = uint32_t(taps * 4 + zero_sum * 2 + add) * 2000 + n;
              flip_kernels::Kernel kernel{finite_floats(taps, seed, 1.0f), zero_sum};
              const auto floats = finite ? finite_floats : mixed_floats;
              std::vector<std::vector<float>> rows;
              std::vector<const float*> sources;
              for (size_t k = 0; k < taps; ++k) rows.push_back(floats(n, seed + 1 + uint32_t(k), 10.0f));
              for (const std::vector<float>& row : rows) sources.push_back(row.data());
              const std::vector<float> centre = floats(n, seed + 100, 10.0f);
              std::vector<float> expected = floats(n + 1, seed + 200, 10.0f), actual = expected;
              generic(kernel, sources.data(), centre.data(), expected.data(), n, add);
              weighted_sum(kernel, sources.data(), centre.data(), actual.data(), n, add);
              EXPECT_TRUE(same_bits(expected, actual, finite ? Nans::same_bits : Nans::any_nan))
                  << taps << " taps, zero sum " << zero_sum << ", add " << add << ", " << n << " pixels, finite "
                  << finite;
            }
  }
}

TEST_F(SimdPaths, ClampedHuntLab) {
  const auto generic = flip_kernels::compiled_for(Path::generic).clamped_hunt_lab;
  const flip_kernels::ColourSpace& space = flip_kernels::colour_space();
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto clamped_hunt_lab = flip_kernels::compiled_for(path).clamped_hunt_lab;
    ASSERT_NE(clamped_hunt_lab, generic);
    for (bool finite : {true, false})
      for (size_t begin : {0u, 3u})
        for (uint32_t n : kLengths) {
          const auto floats = finite ? finite_floats : mixed_floats;
          const size_t size = begin + n + 1;
          // Y/Y_n around [0, 1] and the opponent channels around what a and b reach.
          std::vector<float> expected[3] = {floats(size, n, 1.5f), floats(size, n + 1, 150.0f),
                                            floats(size, n + 2, 150.0f)};
          std::vector<float> actual[3] = {expected[0], expected[1], expected[2]};
          generic(expected[0].data(), expected[1].data(), expected[2].data(), begin, begin + n, space);
          clamped_hunt_lab(actual[0].data(), actual[1].data(), actual[2].data(), begin, begin + n, space);
          for (int plane = 0; plane < 3; ++plane)
            EXPECT_TRUE(same_bits(expected[plane], actual[plane], finite ? Nans::same_bits : Nans::any_nan))
                << "plane " << plane << ", pixels [" << begin << ", " << begin + n << "), finite " << finite;
        }
  }
}

// Finite inputs only, as FLIP's are (it rejects images that are not): log2_lanes reads a NaN's bits as
// a number's, so the NaN that a path's operand order lets through changes the error's value.
TEST_F(SimdPaths, PixelErrors) {
  const auto generic = flip_kernels::compiled_for(Path::generic).pixel_errors;
  const float max_distance = flip_kernels::colour_space().max_distance;
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto pixel_errors = flip_kernels::compiled_for(path).pixel_errors;
    ASSERT_NE(pixel_errors, generic);
    for (bool components : {false, true})
      for (uint32_t n : kLengths) {
        // Lightness, a, b, edges and points of each image, the features around [0, 1].
        std::vector<float> planes[10];
        for (int p = 0; p < 10; ++p) planes[p] = finite_floats(n, n * 10 + p, p % 5 < 3 ? 100.0f : 1.0f);
        const flip_kernels::PerceivedRow reference{planes[0].data(), planes[1].data(), planes[2].data(),
                                                   planes[3].data(), planes[4].data()};
        const flip_kernels::PerceivedRow test{planes[5].data(), planes[6].data(), planes[7].data(), planes[8].data(),
                                              planes[9].data()};
        std::vector<float> expected[3], actual[3];
        for (int o = 0; o < 3; ++o) expected[o] = actual[o] = std::vector<float>(n + 1, -1.0f);
        generic(reference, test, n, max_distance, expected[0].data(), components ? expected[1].data() : nullptr,
                components ? expected[2].data() : nullptr);
        pixel_errors(reference, test, n, max_distance, actual[0].data(), components ? actual[1].data() : nullptr,
                     components ? actual[2].data() : nullptr);
        for (int o = 0; o < 3; ++o)
          EXPECT_TRUE(same_bits(expected[o], actual[o])) << "output " << o << ", " << n << " pixels";
      }
  }
}

// The values a block of two images' floats compares: b is a changed by nothing, by a little and by
// a lot in turn, so that values agree, differ under a threshold and over it.
struct FloatPair {
  std::vector<float> a, b;
};

FloatPair float_pair(size_t n, uint32_t seed) {
  FloatPair pair{finite_floats(n, seed, 8.0f), {}};
  pair.b = pair.a;
  std::mt19937 rng(seed + 7);
  std::uniform_real_distribution<float> step(-1.0f, 1.0f);
  for (float& v : pair.b) {
    const uint32_t kind = rng() % 4;
    if (kind == 1) v += 1e-4f * step(rng);
    if (kind == 2) v += step(rng);
    if (kind == 3) v = std::nextafter(v, 0.0f);
  }
  return pair;
}

::testing::AssertionResult same_tally(const metrics_kernels::ImageTally& x, const metrics_kernels::ImageTally& y) {
  if (same_bits(x.peak, y.peak) && same_bits(x.max_abs, y.max_abs) && same_bits(x.sum_squares, y.sum_squares) &&
      same_bits(x.angle_sum, y.angle_sum) && x.values == y.values && x.texels == y.texels &&
      x.differing == y.differing && x.over == y.over)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << std::hexfloat << "peak " << x.peak << " vs " << y.peak << ", max_abs "
                                       << x.max_abs << " vs " << y.max_abs << ", sum_squares " << x.sum_squares
                                       << " vs " << y.sum_squares << ", values " << x.values << " vs " << y.values
                                       << ", texels " << x.texels << " vs " << y.texels << ", differing " << x.differing
                                       << " vs " << y.differing << ", over " << x.over << " vs " << y.over;
}

TEST_F(SimdPaths, TallyFinite) {
  const auto generic = metrics_kernels::compiled_for(Path::generic).tally_finite;
  const ComparisonContract contracts[2] = {ComparisonContract::floats(1e-6, 1e-3, "simd paths test"),
                                           ComparisonContract::floats(0.0, 0.0, "departures infinite")};
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto tally_finite = metrics_kernels::compiled_for(path).tally_finite;
    ASSERT_NE(tally_finite, generic);
    for (uint32_t channels = 1; channels <= 4; ++channels)
      for (uint32_t texels : {0u, 1u, 3u, 4u, 5u, 17u, 64u, 255u, 1024u})
        for (bool relative : {false, true})
          for (const ComparisonContract* departs :
               {static_cast<const ComparisonContract*>(nullptr), &contracts[0], &contracts[1]})
            // Finite values throughout, then a NaN or infinity in the vector part or the tail.
            for (int spoiled : {0, 1, 2}) {
              const size_t n = size_t(texels) * channels;
              if (spoiled && n == 0) continue;
              FloatPair values = float_pair(n, texels * 100 + channels * 10 + relative * 5 + spoiled);
              if (spoiled) values.b[spoiled == 1 ? 0 : n - 1] = spoiled == 1 ? NAN : -INFINITY;
              metrics_kernels::ImageTally expected{1.5, 0.25, 3.0, 0.0, 7, 3, 2, 1}, actual = expected;
              double expected_worst = 0.5, actual_worst = 0.5;
              const bool expected_finite = generic(values.a.data(), values.b.data(), texels, channels, relative, 1e-3,
                                                   departs, expected, expected_worst);
              const bool actual_finite = tally_finite(values.a.data(), values.b.data(), texels, channels, relative,
                                                      1e-3, departs, actual, actual_worst);
              SCOPED_TRACE(testing::Message()
                           << texels << " texels of " << channels << " channels, relative " << relative << ", contract "
                           << (departs ? departs - contracts : -1) << ", spoiled " << spoiled);
              EXPECT_EQ(expected_finite, actual_finite);
              EXPECT_EQ(expected_finite, spoiled == 0);
              EXPECT_TRUE(same_tally(expected, actual));
              EXPECT_TRUE(same_bits(expected_worst, actual_worst)) << expected_worst << " vs " << actual_worst;
            }
  }
}

TEST_F(SimdPaths, WorstDepartureFinite) {
  const auto generic = metrics_kernels::compiled_for(Path::generic).worst_departure_finite;
  const ComparisonContract contracts[2] = {ComparisonContract::floats(1e-6, 1e-3, "simd paths test"),
                                           ComparisonContract::floats(0.0, 0.0, "departures infinite")};
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto worst_departure_finite = metrics_kernels::compiled_for(path).worst_departure_finite;
    ASSERT_NE(worst_departure_finite, generic);
    for (const ComparisonContract& contract : contracts)
      for (uint32_t n : kLengths)
        for (int spoiled : {0, 1, 2}) {
          if (spoiled && n == 0) continue;
          FloatPair values = float_pair(n, n * 3 + spoiled);
          if (spoiled) values.a[spoiled == 1 ? 0 : n - 1] = spoiled == 1 ? INFINITY : NAN;
          double expected = 0.5, actual = 0.5;
          const bool expected_finite = generic(values.a.data(), values.b.data(), n, contract, expected);
          const bool actual_finite = worst_departure_finite(values.a.data(), values.b.data(), n, contract, actual);
          SCOPED_TRACE(testing::Message()
                       << n << " values, contract " << &contract - contracts << ", spoiled " << spoiled);
          EXPECT_EQ(expected_finite, actual_finite);
          EXPECT_EQ(expected_finite, spoiled == 0);
          EXPECT_TRUE(same_bits(expected, actual)) << expected << " vs " << actual;
        }
  }
}

TEST_F(SimdPaths, LargestByteDifference) {
  const auto generic = metrics_kernels::compiled_for(Path::generic).largest_byte_difference;
  for (Path path : wider_) {
    SCOPED_TRACE(simd::path_name(path));
    const auto largest_byte_difference = metrics_kernels::compiled_for(path).largest_byte_difference;
    ASSERT_NE(largest_byte_difference, generic);
    std::mt19937 rng(5);
    for (uint32_t n : kLengths)
      // Small differences throughout, then the largest (255 at the most) at each end.
      for (size_t largest_at : {size_t(0), size_t(n) - 1, size_t(n)}) {
        std::vector<uint8_t> a(n), b(n);
        for (uint32_t i = 0; i < n; ++i) {
          a[i] = uint8_t(rng());
          b[i] = uint8_t(a[i] + rng() % 7 - 3);
        }
        if (largest_at < n) {
          a[largest_at] = 255;
          b[largest_at] = 0;
        }
        EXPECT_EQ(generic(a.data(), b.data(), n), largest_byte_difference(a.data(), b.data(), n))
            << n << " bytes, largest at " << largest_at;
      }
  }
}

// The paths found are the CPU's, by an independent reading of its flags.
TEST(SimdPathsCpu, MatchCpuinfoFlags) {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line) && line.rfind("flags", 0) != 0) {
  }
  if (line.empty()) GTEST_SKIP() << "no /proc/cpuinfo flags to read";
  std::istringstream words(line);
  bool avx2 = false, avx512f = false;
  for (std::string word; words >> word;) {
    avx2 |= word == "avx2";
    avx512f |= word == "avx512f";
  }
  std::vector<Path> expected = {Path::generic};
  if (avx2) expected.push_back(Path::avx2);
  if (avx512f) expected.push_back(Path::avx512);
  EXPECT_EQ(path_names(simd::supported_paths()), path_names(expected));
  EXPECT_EQ(simd::widest_path(), expected.back());
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
