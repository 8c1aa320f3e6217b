// The format table: raw layout offsets, texel decoding of every encoding on codes whose value
// is known, the half conversions against exact arithmetic, and the NaN texel of each float format.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "passes/core/format.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

FormatInfo info(VkFormat format) { return *format_info(format); }

template <typename T>
std::vector<uint8_t> bytes_of(std::initializer_list<T> values) {
  std::vector<uint8_t> bytes(values.size() * sizeof(T));
  std::memcpy(bytes.data(), values.begin(), bytes.size());
  return bytes;
}

std::vector<float> decode(VkFormat format, std::span<const uint8_t> plane, uint64_t index, uint32_t aspect = 0) {
  const FormatInfo f = info(format);
  std::vector<float> out(aspect_channels(f, aspect));
  decode_texel(f, aspect, plane, index, out.data());
  return out;
}

TEST(Format, TableIsConsistent) {
  for (const FormatInfo& f : all_formats()) {
    SCOPED_TRACE(std::string(f.name));
    EXPECT_EQ(format_info(f.vk)->name, f.name);
    EXPECT_EQ(format_by_name(f.name)->vk, f.vk);
    uint32_t aspect_bytes = 0;
    for (uint32_t a = 0; a < aspect_count(f); ++a) aspect_bytes += aspect_texel_bytes(f, a);
    EXPECT_EQ(raw_image_bytes(f, {1, 1}), aspect_bytes);
  }
  EXPECT_FALSE(format_info(VK_FORMAT_R8G8B8_UNORM));
  EXPECT_FALSE(format_by_name("VK_FORMAT_R8_UNORM"));
}

TEST(Format, MipSizes) {
  EXPECT_EQ(mip_size(7, 0), 7u);
  EXPECT_EQ(mip_size(7, 1), 3u);
  EXPECT_EQ(mip_size(7, 2), 1u);
  EXPECT_EQ(mip_size(7, 5), 1u);
  EXPECT_EQ(mip_size(1280, 4), 80u);
}

TEST(Format, DepthStencilLayoutPutsTheStencilPlaneAfterAllDepthMips) {
  const FormatInfo ds = info(VK_FORMAT_D32_SFLOAT_S8_UINT);
  const ImageExtent extent{4, 2, 1, 2, 3};
  // Depth: mip 0 4*2*4 = 32 bytes, mip 1 2*1*4 = 8 bytes, per layer.
  EXPECT_EQ(raw_subresource_offset(ds, extent, 0, 0, 0), 0u);
  EXPECT_EQ(raw_subresource_offset(ds, extent, 0, 0, 2), 64u);
  EXPECT_EQ(raw_subresource_offset(ds, extent, 0, 1, 0), 96u);
  EXPECT_EQ(raw_subresource_offset(ds, extent, 0, 1, 2), 112u);
  // Stencil: mip 0 8 bytes, mip 1 2 bytes, per layer.
  EXPECT_EQ(raw_subresource_offset(ds, extent, 1, 0, 0), 120u);
  EXPECT_EQ(raw_subresource_offset(ds, extent, 1, 1, 2), 120u + 24u + 4u);
  EXPECT_EQ(raw_subresource_bytes(ds, extent, 1, 1), 2u);
  EXPECT_EQ(raw_image_bytes(ds, extent), 150u);
}

TEST(Format, ThreeDimensionalMipsHalveDepthToo) {
  const FormatInfo rgba8 = info(VK_FORMAT_R8G8B8A8_UNORM);
  const ImageExtent extent{8, 4, 4, 3, 1};
  EXPECT_EQ(raw_subresource_bytes(rgba8, extent, 0, 0), 512u);
  EXPECT_EQ(raw_subresource_bytes(rgba8, extent, 0, 1), 64u);  // 4x2x2
  EXPECT_EQ(raw_subresource_bytes(rgba8, extent, 0, 2), 8u);   // 2x1x1
  EXPECT_EQ(raw_subresource_offset(rgba8, extent, 0, 2, 0), 576u);
  EXPECT_EQ(raw_image_bytes(rgba8, extent), 584u);
  EXPECT_EQ(raw_image_bytes(info(VK_FORMAT_R16G16B16A16_SFLOAT), {1280, 720}), 1280u * 720u * 8u);
}

TEST(Format, DecodesEightAndSixteenBitCodes) {
  const std::vector<uint8_t> rgba = {0, 255, 128, 51};
  EXPECT_EQ(decode(VK_FORMAT_R8G8B8A8_UNORM, rgba, 0), (std::vector<float>{0.0f, 1.0f, 128 / 255.0f, 0.2f}));
  const std::vector<float> srgb = decode(VK_FORMAT_R8G8B8A8_SRGB, rgba, 0);
  EXPECT_EQ(srgb[0], 0.0f);
  EXPECT_FLOAT_EQ(srgb[1], 1.0f);
  EXPECT_NEAR(srgb[2], 0.2158605f, 1e-6f);  // sRGB 128/255 in linear
  EXPECT_FLOAT_EQ(srgb[3], 0.2f);           // alpha is linear
  EXPECT_EQ(decode(VK_FORMAT_R8_UINT, rgba, 1), std::vector<float>{255.0f});
  EXPECT_EQ(decode(VK_FORMAT_R8G8_UNORM, rgba, 1), (std::vector<float>{128 / 255.0f, 0.2f}));

  const std::vector<uint8_t> shorts = bytes_of<uint16_t>({0, 65535, 32768, 40000});
  EXPECT_EQ(decode(VK_FORMAT_R16_UNORM, shorts, 1), std::vector<float>{1.0f});
  EXPECT_EQ(decode(VK_FORMAT_D16_UNORM, shorts, 2), std::vector<float>{32768 / 65535.0f});
  EXPECT_EQ(decode(VK_FORMAT_R16G16_UNORM, shorts, 0), (std::vector<float>{0.0f, 1.0f}));
  EXPECT_EQ(decode(VK_FORMAT_R16_UINT, shorts, 3), std::vector<float>{40000.0f});
}

TEST(Format, DecodesFloatCodes) {
  const std::vector<uint8_t> halves = bytes_of<uint16_t>({0x3C00, 0xC000, 0x7BFF, 0x0001, 0x8000, 0x7C00});
  EXPECT_EQ(decode(VK_FORMAT_R16G16B16A16_SFLOAT, halves, 0),
            (std::vector<float>{1.0f, -2.0f, 65504.0f, std::ldexp(1.0f, -24)}));
  const std::vector<float> rg = decode(VK_FORMAT_R16G16_SFLOAT, halves, 2);
  EXPECT_TRUE(rg[0] == 0.0f && std::signbit(rg[0]));
  EXPECT_EQ(rg[1], INFINITY);
  EXPECT_TRUE(std::isnan(decode(VK_FORMAT_R16_SFLOAT, bytes_of<uint16_t>({0x7E00}), 0)[0]));

  const std::vector<uint8_t> floats = bytes_of<float>({3.5f, -0.0f, 1e-40f, -INFINITY});
  EXPECT_EQ(decode(VK_FORMAT_R32G32B32A32_SFLOAT, floats, 0), (std::vector<float>{3.5f, -0.0f, 1e-40f, -INFINITY}));
  EXPECT_TRUE(std::signbit(decode(VK_FORMAT_R32G32_SFLOAT, floats, 0)[1]));
  EXPECT_EQ(decode(VK_FORMAT_D32_SFLOAT, floats, 2), std::vector<float>{1e-40f});

  const std::vector<uint8_t> words = bytes_of<uint32_t>({123456, 0, 4000000000u, 7});
  EXPECT_EQ(decode(VK_FORMAT_R32_UINT, words, 0), std::vector<float>{123456.0f});
  EXPECT_EQ(decode(VK_FORMAT_R32G32B32A32_UINT, bytes_of<uint32_t>({1, 2, 3, 4}), 0), (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(decode(VK_FORMAT_R32G32_UINT, words, 1), (std::vector<float>{4e9f, 7.0f}));
}

TEST(Format, DecodesPackedWords) {
  // A2B10G10R10: r bits 0-9, g 10-19, b 20-29, a 30-31.
  const std::vector<uint8_t> a2b10 = bytes_of<uint32_t>({0xC00FFC00u, 0x000003FFu, 0x40000200u, 0x3FF00000u});
  EXPECT_EQ(decode(VK_FORMAT_A2B10G10R10_UNORM_PACK32, a2b10, 0), (std::vector<float>{0, 1, 0, 1}));
  EXPECT_EQ(decode(VK_FORMAT_A2B10G10R10_UNORM_PACK32, a2b10, 1), (std::vector<float>{1, 0, 0, 0}));
  EXPECT_EQ(decode(VK_FORMAT_A2B10G10R10_UNORM_PACK32, a2b10, 2), (std::vector<float>{512 / 1023.0f, 0, 0, 1 / 3.0f}));
  EXPECT_EQ(decode(VK_FORMAT_A2B10G10R10_UNORM_PACK32, a2b10, 3), (std::vector<float>{0, 0, 1, 0}));

  // B10G11R11: r bits 0-10 and g 11-21 (5-bit exponent, 6-bit mantissa), b 22-31 (5-bit
  // mantissa); exponent bias 15, so 1.0 is 0x3c0 in r and g and 0x1e0 in b.
  const auto word = [](uint32_t r, uint32_t g, uint32_t b) { return r | g << 11 | b << 22; };
  const std::vector<uint8_t> b10 = bytes_of<uint32_t>({
      word(0x3c0, 0x3c0, 0x1e0),  // 1, 1, 1
      word(0x7bf, 0x001, 0x3df),  // largest r, smallest denormal g, largest b
      word(0x7c0, 0x7c1, 0x000),  // inf, NaN, 0
      word(0x400, 0x3e0, 0x200),  // 2, 1.5, 2
  });
  EXPECT_EQ(decode(VK_FORMAT_B10G11R11_UFLOAT_PACK32, b10, 0), (std::vector<float>{1, 1, 1}));
  EXPECT_EQ(decode(VK_FORMAT_B10G11R11_UFLOAT_PACK32, b10, 1),
            (std::vector<float>{65024.0f, std::ldexp(1.0f, -20), 64512.0f}));
  const std::vector<float> special = decode(VK_FORMAT_B10G11R11_UFLOAT_PACK32, b10, 2);
  EXPECT_EQ(special[0], INFINITY);
  EXPECT_TRUE(std::isnan(special[1]));
  EXPECT_EQ(special[2], 0.0f);
  EXPECT_EQ(decode(VK_FORMAT_B10G11R11_UFLOAT_PACK32, b10, 3), (std::vector<float>{2.0f, 1.5f, 2.0f}));
}

TEST(Format, DecodesDepthAndStencilPlanes) {
  const FormatInfo ds = info(VK_FORMAT_D32_SFLOAT_S8_UINT);
  const ImageExtent extent{3, 1};
  std::vector<uint8_t> raw = bytes_of<float>({0.25f, 1.0f, 0.0f});
  raw.insert(raw.end(), {7, 0, 255});
  const std::span<const uint8_t> all(raw);
  const std::span<const uint8_t> stencil = all.subspan(raw_subresource_offset(ds, extent, 1, 0, 0));
  EXPECT_EQ(decode(VK_FORMAT_D32_SFLOAT_S8_UINT, all, 0), std::vector<float>{0.25f});
  EXPECT_EQ(decode(VK_FORMAT_D32_SFLOAT_S8_UINT, all, 1), std::vector<float>{1.0f});
  EXPECT_EQ(decode(VK_FORMAT_D32_SFLOAT_S8_UINT, stencil, 0, 1), std::vector<float>{7.0f});
  EXPECT_EQ(decode(VK_FORMAT_D32_SFLOAT_S8_UINT, stencil, 2, 1), std::vector<float>{255.0f});
}

TEST(Format, HalfCodesRoundTripThroughFloat) {
  for (uint32_t code = 0; code < 65536; ++code) {
    const uint16_t h = uint16_t(code);
    const float f = half_to_float(h);
    const bool nan_code = (h & 0x7c00) == 0x7c00 && (h & 0x3ff);
    if (nan_code) {
      EXPECT_TRUE(std::isnan(f)) << code;
      const uint16_t back = float_to_half(f);
      EXPECT_TRUE((back & 0x7c00) == 0x7c00 && (back & 0x3ff)) << code;
      continue;
    }
    // The exact value, from the definition of binary16.
    const int exponent = (h >> 10) & 31, mantissa = h & 1023;
    double exact = exponent == 0    ? std::ldexp(double(mantissa), -24)
                   : exponent == 31 ? INFINITY
                                    : std::ldexp(double(1024 + mantissa), exponent - 25);
    if (h & 0x8000) exact = -exact;
    ASSERT_EQ(double(f), exact) << code;
    ASSERT_EQ(std::signbit(f), bool(h & 0x8000)) << code;
    ASSERT_EQ(float_to_half(f), h) << code;
  }
}

// The nearest binary16 to |x| computed in double: halves and the midpoints between adjacent
// halves are exact in double, so comparing x with a midpoint is exact; ties go to the even code.
uint16_t nearest_half(double x) {
  const double magnitude = std::fabs(x);
  const uint16_t sign = std::signbit(x) ? 0x8000 : 0;
  const auto value = [](uint32_t code) { return double(half_to_float(uint16_t(code))); };
  // Codes 0..0x7c00 are ordered by value; 65520 is the midpoint between 65504 and the next
  // power-of-two step, beyond which everything rounds to infinity (code 0x7c00 is even).
  if (magnitude >= 65520.0) return sign | 0x7c00;
  uint32_t lo = 0, hi = 0x7bff;
  while (lo < hi) {
    const uint32_t mid = (lo + hi + 1) / 2;
    if (value(mid) <= magnitude)
      lo = mid;
    else
      hi = mid - 1;
  }
  const double midpoint = (value(lo) + value(lo + 1)) / 2;
  uint32_t code = lo;
  if (magnitude > midpoint || (magnitude == midpoint && (lo & 1))) code = lo + 1;
  return uint16_t(sign | code);
}

TEST(Format, FloatToHalfRoundsToNearestEven) {
  std::vector<float> samples = {0.0f,
                                -0.0f,
                                65504.0f,
                                65519.99f,
                                65520.0f,
                                1e10f,
                                -1e10f,
                                1e-30f,
                                1e-40f,
                                std::ldexp(1.0f, -25),
                                std::ldexp(1.5f, -25),
                                std::ldexp(1.0f, -26),
                                std::nextafter(std::ldexp(1.0f, -25), 1.0f),
                                std::ldexp(1.0f, -14) * (1.0f - 1 / 2048.0f)};
  std::mt19937 rng(17);
  // Every midpoint between adjacent halves in a few binades, and its neighbouring floats.
  for (uint32_t code = 0; code < 0x7bff; code += 1 + rng() % 29) {
    const float mid = float((double(half_to_float(uint16_t(code))) + half_to_float(uint16_t(code + 1))) / 2);
    for (float f : {mid, std::nextafter(mid, 0.0f), std::nextafter(mid, INFINITY)}) {
      samples.push_back(f);
      samples.push_back(-f);
    }
  }
  // Random floats spanning the half range, its subnormals and beyond.
  for (int i = 0; i < 4000; ++i) {
    const uint32_t exponent = 127 - 28 + rng() % 46;
    const uint32_t bits = (rng() & 0x80000000u) | exponent << 23 | (rng() & 0x7fffff);
    float f;
    std::memcpy(&f, &bits, 4);
    samples.push_back(f);
  }
  ASSERT_GT(samples.size(), 3000u);
  for (float f : samples) ASSERT_EQ(float_to_half(f), nearest_half(f)) << std::hexfloat << f;
  EXPECT_TRUE(std::isnan(half_to_float(float_to_half(NAN))));
  EXPECT_EQ(float_to_half(INFINITY), 0x7c00);
  EXPECT_EQ(float_to_half(-INFINITY), 0xfc00);
}

TEST(Format, SrgbTransferRoundTrips) {
  for (int code = 0; code < 256; ++code) {
    const float c = code / 255.0f;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(c)), c, 1e-5f) << code;
  }
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404114f, 1e-6f);
}

TEST(Format, QuietNanTexelIsNanInEveryChannelOfEachFloatColourFormat) {
  uint32_t float_formats = 0;
  for (const FormatInfo& f : all_formats()) {
    SCOPED_TRACE(std::string(f.name));
    if (!is_float_colour(f)) {
      EXPECT_THROW(quiet_nan_texel(f), std::invalid_argument);
      continue;
    }
    ++float_formats;
    EXPECT_FALSE(f.is_depth);
    const std::vector<uint8_t> texel = quiet_nan_texel(f);
    ASSERT_EQ(texel.size(), f.texel_bytes);
    for (float value : decode(f.vk, texel, 0)) EXPECT_TRUE(std::isnan(value));
  }
  EXPECT_GE(float_formats, 3u) << "half, float and B10G11R11 at least";
  EXPECT_EQ(quiet_nan_texel(info(VK_FORMAT_R16_SFLOAT)), bytes_of<uint16_t>({0x7E00}));
  EXPECT_EQ(quiet_nan_texel(info(VK_FORMAT_R32_SFLOAT)), bytes_of<uint32_t>({0x7FC00000}));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
