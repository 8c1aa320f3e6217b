#include "compare/decoded_image.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "compare/simd_kernels.h"

namespace nightcap {
namespace {

// Halves to floats, eight at a time (compare/simd.h): the half's magnitude bits shifted into a
// float's place read as a float 2^-112 times too small (subnormals included), so one multiply
// rebiases it; what comes out at 2^16 or more was infinity or NaN and gets the float's all-ones
// exponent, keeping the NaN's payload. Every half gives half_to_float's value (a NaN a NaN).
[[gnu::always_inline]] inline void halves_to_floats_body(const uint8_t* halves, float* out, uint64_t n) {
  using simd::Floats8, simd::Halves8, simd::Words8;
  uint64_t i = 0;
  for (; i + 8 <= n; i += 8) {
    Halves8 h;
    std::memcpy(&h, halves + 2 * i, sizeof h);
    const Words8 bits = __builtin_convertvector(h, Words8);
    // A cast between vector types of one size keeps the bits.
    const Floats8 magnitude = (Floats8)((bits & 0x7fffu) << 13) * 0x1p112f;
    Words8 value = (Words8)magnitude;
    value |= (Words8)(magnitude >= 65536.0f) & (255u << 23);
    value |= (bits & 0x8000u) << 16;
    std::memcpy(out + i, &value, sizeof value);
  }
  for (; i < n; ++i) {
    uint16_t h;
    std::memcpy(&h, halves + 2 * i, 2);
    out[i] = half_to_float(h);
  }
}
using HalvesToFloatsPaths = simd::Compiled<halves_to_floats_body, simd::Path::avx2>;
constexpr auto& halves_to_floats = HalvesToFloatsPaths::dispatch;

}  // namespace

decode_kernels::Functions decode_kernels::compiled_for(simd::Path path) { return {HalvesToFloatsPaths::on(path)}; }

void decode_values(const FormatInfo& f, uint32_t aspect, std::span<const uint8_t> plane, float* out) {
  const uint32_t channels = aspect_channels(f, aspect);
  const uint64_t texels = plane.size() / aspect_texel_bytes(f, aspect);
  if (aspect == 0 && f.encoding == ChannelEncoding::sfloat16) {
    halves_to_floats(plane.data(), out, texels * channels);
    return;
  }
  if (aspect == 0 && (f.encoding == ChannelEncoding::unorm8 || f.encoding == ChannelEncoding::srgb8)) {
    // A byte per channel: decode_texel's rules (sRGB colour, linear alpha) applied once per code
    // and channel, then looked up; the table is kept for the next call on the same format.
    thread_local VkFormat tabled = VK_FORMAT_UNDEFINED;
    thread_local std::array<std::array<float, 256>, 4> table;
    if (tabled != f.vk) {
      for (uint32_t code = 0; code < 256; ++code) {
        const std::array<uint8_t, 4> texel{uint8_t(code), uint8_t(code), uint8_t(code), uint8_t(code)};
        float values[4];
        decode_texel(f, aspect, texel, 0, values);
        for (uint32_t c = 0; c < channels; ++c) table[c][code] = values[c];
      }
      tabled = f.vk;
    }
    if (channels == 4) {  // RGBA: the loop over channels unrolled (FLIP decodes displayed images so)
      for (uint64_t t = 0; t < texels; ++t) {
        const uint8_t* code = plane.data() + 4 * t;
        float* value = out + 4 * t;
        value[0] = table[0][code[0]];
        value[1] = table[1][code[1]];
        value[2] = table[2][code[2]];
        value[3] = table[3][code[3]];
      }
      return;
    }
    for (uint64_t t = 0; t < texels; ++t)
      for (uint32_t c = 0; c < channels; ++c) out[t * channels + c] = table[c][plane[t * channels + c]];
    return;
  }
  if (aspect == 0 && f.encoding == ChannelEncoding::sfloat32) {
    std::memcpy(out, plane.data(), texels * channels * sizeof(float));
    return;
  }
  for (uint64_t t = 0; t < texels; ++t) decode_texel(f, aspect, plane, t, out + t * channels);
}

DecodedImage::DecodedImage(const ResourceRecord& record, std::span<const uint8_t> raw)
    : format_(*format_info(record.format)), extent_(record.extent) {
  const uint32_t aspects = aspect_count(format_);
  for (uint32_t aspect = 0; aspect < aspects; ++aspect) {
    const uint64_t bytes = raw_subresource_offset(format_, extent_, aspect + 1, 0, 0) -
                           raw_subresource_offset(format_, extent_, aspect, 0, 0);
    aspect_begin_[aspect + 1] =
        aspect_begin_[aspect] + bytes / aspect_texel_bytes(format_, aspect) * aspect_channels(format_, aspect);
  }
  values_.resize(aspect_begin_[aspects]);
  for (uint32_t aspect = 0; aspect < aspects; ++aspect) {
    const uint64_t begin = raw_subresource_offset(format_, extent_, aspect, 0, 0);
    const uint64_t end = raw_subresource_offset(format_, extent_, aspect + 1, 0, 0);
    decode_values(format_, aspect, raw.subspan(begin, end - begin), values_.data() + aspect_begin_[aspect]);
  }
}

std::span<const float> DecodedImage::aspect(uint32_t aspect) const {
  return std::span<const float>(values_).subspan(aspect_begin_[aspect],
                                                 aspect_begin_[aspect + 1] - aspect_begin_[aspect]);
}

std::span<const float> DecodedImage::subresource(uint32_t aspect, uint32_t mip, uint32_t layer) const {
  const uint32_t texel_bytes = aspect_texel_bytes(format_, aspect), channels = aspect_channels(format_, aspect);
  const uint64_t offset = raw_subresource_offset(format_, extent_, aspect, mip, layer) -
                          raw_subresource_offset(format_, extent_, aspect, 0, 0);
  return this->aspect(aspect).subspan(offset / texel_bytes * channels,
                                      raw_subresource_bytes(format_, extent_, aspect, mip) / texel_bytes * channels);
}

ResourcePair::ResourcePair(const ResourceRecord& a, std::span<const uint8_t> a_raw, const ResourceRecord& b,
                           std::span<const uint8_t> b_raw)
    : a(a), b(b), a_raw(a_raw), b_raw(b_raw) {
  same_shape_ = a.is_buffer == b.is_buffer && a_raw.size() == b_raw.size() &&
                (a.is_buffer || (a.format == b.format && a.extent.width == b.extent.width &&
                                 a.extent.height == b.extent.height && a.extent.depth == b.extent.depth &&
                                 a.extent.mips == b.extent.mips && a.extent.layers == b.extent.layers));
}

bool ResourcePair::same_bytes() const {
  return a_raw.size() == b_raw.size() && std::equal(a_raw.begin(), a_raw.end(), b_raw.begin());
}

void ResourcePair::for_each_block(uint32_t aspect,
                                  const std::function<void(const float*, const float*, uint64_t)>& visit) const {
  const FormatInfo format = *format_info(a.format);
  const uint64_t begin = raw_subresource_offset(format, a.extent, aspect, 0, 0);
  const uint64_t end = raw_subresource_offset(format, a.extent, aspect + 1, 0, 0);
  const uint64_t texel_bytes = aspect_texel_bytes(format, aspect), channels = aspect_channels(format, aspect);
  thread_local std::vector<float> values_a, values_b;
  values_a.resize(kBlockTexels * channels);
  values_b.resize(kBlockTexels * channels);
  for (uint64_t at = begin; at < end; at += kBlockTexels * texel_bytes) {
    const uint64_t bytes = std::min(end - at, kBlockTexels * texel_bytes);
    decode_values(format, aspect, a_raw.subspan(at, bytes), values_a.data());
    decode_values(format, aspect, b_raw.subspan(at, bytes), values_b.data());
    visit(values_a.data(), values_b.data(), bytes / texel_bytes);
  }
}

const DecodedImage& ResourcePair::a_values() const {
  if (!a_values_) a_values_.emplace(a, a_raw);
  return *a_values_;
}

const DecodedImage& ResourcePair::b_values() const {
  if (!b_values_) b_values_.emplace(b, b_raw);
  return *b_values_;
}

}  // namespace nightcap
