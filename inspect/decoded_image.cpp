#include "inspect/decoded_image.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>

namespace nightcap {
namespace {

// Every half's float, computed once: a table read per channel instead of decode_texel's switch
// and bit work per texel (most of a diff's float outputs are half).
const std::array<float, 65536>& half_table() {
  static const std::unique_ptr<std::array<float, 65536>> table = [] {
    auto t = std::make_unique<std::array<float, 65536>>();
    for (uint32_t h = 0; h < 65536; ++h) (*t)[h] = half_to_float(uint16_t(h));
    return t;
  }();
  return *table;
}

void decode_plane(const FormatInfo& f, uint32_t aspect, std::span<const uint8_t> plane, float* out) {
  const uint32_t channels = aspect_channels(f, aspect);
  const uint64_t texels = plane.size() / aspect_texel_bytes(f, aspect);
  if (aspect == 0 && f.encoding == ChannelEncoding::sfloat16) {
    const std::array<float, 65536>& table = half_table();
    for (uint64_t i = 0; i < texels * channels; ++i) {
      uint16_t h;
      std::memcpy(&h, plane.data() + 2 * i, 2);
      out[i] = table[h];
    }
    return;
  }
  if (aspect == 0 && (f.encoding == ChannelEncoding::unorm8 || f.encoding == ChannelEncoding::srgb8)) {
    // A byte per channel: decode_texel's rules (sRGB colour, linear alpha) applied once per code
    // and channel, then looked up.
    std::array<std::array<float, 256>, 4> table;
    for (uint32_t code = 0; code < 256; ++code) {
      const std::array<uint8_t, 4> texel{uint8_t(code), uint8_t(code), uint8_t(code), uint8_t(code)};
      float values[4];
      decode_texel(f, aspect, texel, 0, values);
      for (uint32_t c = 0; c < channels; ++c) table[c][code] = values[c];
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

}  // namespace

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
    decode_plane(format_, aspect, raw.subspan(begin, end - begin), values_.data() + aspect_begin_[aspect]);
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

const DecodedImage& ResourcePair::a_values() const {
  if (!a_values_) a_values_.emplace(a, a_raw);
  return *a_values_;
}

const DecodedImage& ResourcePair::b_values() const {
  if (!b_values_) b_values_.emplace(b, b_raw);
  return *b_values_;
}

}  // namespace nightcap
