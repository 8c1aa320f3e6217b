#include "passes/core/format.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace nightcap {
namespace {

using E = ChannelEncoding;

const std::vector<FormatInfo> kFormats = {
    {VK_FORMAT_R8_UNORM, "R8_UNORM", E::unorm8, 1, 1},
    {VK_FORMAT_R8G8_UNORM, "R8G8_UNORM", E::unorm8, 2, 2},
    {VK_FORMAT_R8G8B8A8_UNORM, "R8G8B8A8_UNORM", E::unorm8, 4, 4},
    {VK_FORMAT_R8G8B8A8_SRGB, "R8G8B8A8_SRGB", E::srgb8, 4, 4},
    {VK_FORMAT_R8_UINT, "R8_UINT", E::uint8, 1, 1},
    {VK_FORMAT_R16_UNORM, "R16_UNORM", E::unorm16, 1, 2},
    {VK_FORMAT_R16G16_UNORM, "R16G16_UNORM", E::unorm16, 2, 4},
    {VK_FORMAT_R16G16B16A16_UNORM, "R16G16B16A16_UNORM", E::unorm16, 4, 8},
    {VK_FORMAT_R16_UINT, "R16_UINT", E::uint16, 1, 2},
    {VK_FORMAT_R16_SFLOAT, "R16_SFLOAT", E::sfloat16, 1, 2},
    {VK_FORMAT_R16G16_SFLOAT, "R16G16_SFLOAT", E::sfloat16, 2, 4},
    {VK_FORMAT_R16G16B16A16_SFLOAT, "R16G16B16A16_SFLOAT", E::sfloat16, 4, 8},
    {VK_FORMAT_R32_SFLOAT, "R32_SFLOAT", E::sfloat32, 1, 4},
    {VK_FORMAT_R32G32_SFLOAT, "R32G32_SFLOAT", E::sfloat32, 2, 8},
    {VK_FORMAT_R32G32B32A32_SFLOAT, "R32G32B32A32_SFLOAT", E::sfloat32, 4, 16},
    {VK_FORMAT_R32_UINT, "R32_UINT", E::uint32, 1, 4},
    {VK_FORMAT_R32G32_UINT, "R32G32_UINT", E::uint32, 2, 8},
    {VK_FORMAT_R32G32B32A32_UINT, "R32G32B32A32_UINT", E::uint32, 4, 16},
    {VK_FORMAT_A2B10G10R10_UNORM_PACK32, "A2B10G10R10_UNORM_PACK32", E::packed_a2b10g10r10, 4, 4},
    {VK_FORMAT_B10G11R11_UFLOAT_PACK32, "B10G11R11_UFLOAT_PACK32", E::packed_b10g11r11, 3, 4},
    {VK_FORMAT_D16_UNORM, "D16_UNORM", E::unorm16, 1, 2, true, false},
    {VK_FORMAT_D32_SFLOAT, "D32_SFLOAT", E::sfloat32, 1, 4, true, false},
    {VK_FORMAT_D32_SFLOAT_S8_UINT, "D32_SFLOAT_S8_UINT", E::depth32_stencil8, 2, 4, true, true},
};

// 10- and 11-bit floats have half's 5-bit exponent and bias: their bits are a half's, with the
// mantissa cut short.
float unsigned_small_float(uint32_t bits, int mantissa_bits) {
  return half_to_float(static_cast<uint16_t>(bits << (10 - mantissa_bits)));
}

// The 256 linear values of the sRGB codes, computed once: pow per channel dominated decoding
// displayed images.
float srgb_code_to_linear(uint8_t code) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t;
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(i / 255.0f);
    return t;
  }();
  return table[code];
}

template <typename T>
T load(std::span<const uint8_t> plane, uint64_t byte_offset) {
  T value;
  std::memcpy(&value, plane.data() + byte_offset, sizeof(T));
  return value;
}

}  // namespace

std::optional<FormatInfo> format_info(VkFormat format) {
  for (const FormatInfo& f : kFormats)
    if (f.vk == format) return f;
  return std::nullopt;
}

std::optional<FormatInfo> format_by_name(std::string_view name) {
  for (const FormatInfo& f : kFormats)
    if (f.name == name) return f;
  return std::nullopt;
}

const std::vector<FormatInfo>& all_formats() { return kFormats; }

uint32_t mip_size(uint32_t base, uint32_t mip) { return std::max(1u, base >> mip); }

uint32_t aspect_count(const FormatInfo& format) { return format.has_stencil ? 2 : 1; }

uint32_t aspect_texel_bytes(const FormatInfo& format, uint32_t aspect) { return aspect == 1 ? 1 : format.texel_bytes; }

uint32_t aspect_channels(const FormatInfo& format, uint32_t aspect) {
  if (format.has_stencil) return 1;
  (void)aspect;
  return format.channels;
}

uint64_t raw_subresource_bytes(const FormatInfo& format, const ImageExtent& extent, uint32_t aspect, uint32_t mip) {
  return uint64_t(mip_size(extent.width, mip)) * mip_size(extent.height, mip) * mip_size(extent.depth, mip) *
         aspect_texel_bytes(format, aspect);
}

uint64_t raw_subresource_offset(const FormatInfo& format, const ImageExtent& extent, uint32_t aspect, uint32_t mip,
                                uint32_t layer) {
  uint64_t offset = 0;
  for (uint32_t a = 0; a < aspect; ++a)
    for (uint32_t m = 0; m < extent.mips; ++m) offset += raw_subresource_bytes(format, extent, a, m) * extent.layers;
  for (uint32_t m = 0; m < mip; ++m) offset += raw_subresource_bytes(format, extent, aspect, m) * extent.layers;
  return offset + raw_subresource_bytes(format, extent, aspect, mip) * layer;
}

uint64_t raw_image_bytes(const FormatInfo& format, const ImageExtent& extent) {
  return raw_subresource_offset(format, extent, aspect_count(format), 0, 0);
}

bool is_float_colour(const FormatInfo& format) {
  return !format.is_depth &&
         (format.encoding == E::sfloat16 || format.encoding == E::sfloat32 || format.encoding == E::packed_b10g11r11);
}

bool is_float(const FormatInfo& format) {
  return format.encoding == E::sfloat16 || format.encoding == E::sfloat32 || format.encoding == E::packed_b10g11r11 ||
         format.encoding == E::depth32_stencil8;
}

std::vector<uint8_t> quiet_nan_texel(const FormatInfo& format) {
  if (!is_float_colour(format)) throw std::invalid_argument(std::string(format.name) + " holds no NaN");
  std::vector<uint8_t> texel(format.texel_bytes);
  auto fill = [&](auto nan) {
    for (size_t offset = 0; offset + sizeof(nan) <= texel.size(); offset += sizeof(nan))
      std::memcpy(texel.data() + offset, &nan, sizeof(nan));
  };
  if (format.encoding == E::sfloat16)
    fill(uint16_t(0x7E00));
  else if (format.encoding == E::sfloat32)
    fill(uint32_t(0x7FC00000));
  else  // B10G11R11: each small float's exponent all ones, its top mantissa bit set (r, g 5+6 bits; b 5+5)
    fill(uint32_t(0x7E0u | (0x7E0u << 11) | (0x3F0u << 22)));
  return texel;
}

double code_scale(const FormatInfo& format) {
  switch (format.encoding) {
    case E::packed_a2b10g10r10:
      return 1023.0;
    case E::unorm16:
      return 65535.0;
    default:
      return 255.0;
  }
}

float half_to_float(uint16_t h) {
  const uint32_t sign = (h >> 15) & 1, exponent = (h >> 10) & 31, mantissa = h & 1023;
  float value;
  if (exponent == 0) {
    value = static_cast<float>(mantissa) * 0x1p-24f;  // subnormal: exact, a power-of-two scale
  } else if (exponent == 31) {
    value = mantissa ? NAN : INFINITY;
  } else {
    // A normal half is a normal float: rebias the exponent, widen the mantissa.
    const uint32_t bits = ((exponent + 127 - 15) << 23) | (mantissa << 13);
    std::memcpy(&value, &bits, 4);
  }
  return sign ? -value : value;
}

float half_rounded(float f) { return half_to_float(float_to_half(std::min(f, 65504.0f))); }

uint16_t float_to_half(float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  uint32_t sign = (bits >> 16) & 0x8000;
  int32_t exponent = static_cast<int32_t>((bits >> 23) & 0xff) - 127 + 15;
  uint32_t mantissa = bits & 0x7fffff;
  if (((bits >> 23) & 0xff) == 0xff) return static_cast<uint16_t>(sign | 0x7c00 | (mantissa ? 0x200 : 0));
  if (exponent >= 31) return static_cast<uint16_t>(sign | 0x7c00);
  if (exponent <= 0) {
    if (exponent < -10) return static_cast<uint16_t>(sign);
    mantissa |= 0x800000;
    uint32_t shift = static_cast<uint32_t>(14 - exponent);
    uint32_t half_mantissa = mantissa >> shift;
    uint32_t rest = mantissa & ((1u << shift) - 1), halfway = 1u << (shift - 1);
    if (rest > halfway || (rest == halfway && (half_mantissa & 1))) ++half_mantissa;
    return static_cast<uint16_t>(sign | half_mantissa);
  }
  uint32_t half = sign | (static_cast<uint32_t>(exponent) << 10) | (mantissa >> 13);
  uint32_t rest = mantissa & 0x1fff;
  if (rest > 0x1000 || (rest == 0x1000 && (half & 1))) ++half;
  return static_cast<uint16_t>(half);
}

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

float linear_to_srgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

void decode_texel(const FormatInfo& format, uint32_t aspect, std::span<const uint8_t> plane, uint64_t index,
                  float* out) {
  const uint64_t base = index * aspect_texel_bytes(format, aspect);
  switch (format.encoding) {
    case E::unorm8:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = plane[base + c] / 255.0f;
      return;
    case E::srgb8:
      for (uint32_t c = 0; c < format.channels; ++c)
        out[c] = c == 3 ? plane[base + c] / 255.0f : srgb_code_to_linear(plane[base + c]);
      return;
    case E::uint8:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = plane[base + c];
      return;
    case E::unorm16:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = load<uint16_t>(plane, base + 2 * c) / 65535.0f;
      return;
    case E::uint16:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = load<uint16_t>(plane, base + 2 * c);
      return;
    case E::sfloat16:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = half_to_float(load<uint16_t>(plane, base + 2 * c));
      return;
    case E::sfloat32:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = load<float>(plane, base + 4 * c);
      return;
    case E::uint32:
      for (uint32_t c = 0; c < format.channels; ++c) out[c] = static_cast<float>(load<uint32_t>(plane, base + 4 * c));
      return;
    case E::packed_a2b10g10r10: {
      uint32_t w = load<uint32_t>(plane, base);
      out[0] = (w & 1023) / 1023.0f;
      out[1] = ((w >> 10) & 1023) / 1023.0f;
      out[2] = ((w >> 20) & 1023) / 1023.0f;
      out[3] = (w >> 30) / 3.0f;
      return;
    }
    case E::packed_b10g11r11: {
      uint32_t w = load<uint32_t>(plane, base);
      out[0] = unsigned_small_float(w & 0x7ff, 6);
      out[1] = unsigned_small_float((w >> 11) & 0x7ff, 6);
      out[2] = unsigned_small_float(w >> 22, 5);
      return;
    }
    case E::depth32_stencil8:
      out[0] = aspect == 1 ? static_cast<float>(plane[base]) : load<float>(plane, base);
      return;
  }
}

}  // namespace nightcap
