// An image's texels decoded to floats once, so that the metrics of a diff (comparison,
// contract, thresholds, FLIP) each read the values instead of decoding every texel again.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

class DecodedImage {
 public:
  // `raw` holds `record`'s image in format.h's raw layout; values as decode_texel gives them.
  DecodedImage(const ResourceRecord& record, std::span<const uint8_t> raw);

  // One aspect's values in raw-layout order (mips, layers, slices, rows), aspect_channels
  // floats per texel.
  std::span<const float> aspect(uint32_t aspect) const;
  // The values of one subresource of one aspect: aspect_channels floats per texel, rows top
  // to bottom, slices one after another.
  std::span<const float> subresource(uint32_t aspect, uint32_t mip, uint32_t layer) const;

 private:
  FormatInfo format_;
  ImageExtent extent_;
  std::array<uint64_t, 3> aspect_begin_{};  // where each aspect's values start in values_
  std::vector<float> values_;
};

// Texels of an image aspect (raw layout, whole texels) decoded to floats as DecodedImage holds them.
void decode_values(const FormatInfo& format, uint32_t aspect, std::span<const uint8_t> texels, float* out);

// Two versions of one resource, as a diff compares them: records, raw bytes, and for images of
// the same shape their decoded values, decoded on first use and shared by every metric.
class ResourcePair {
 public:
  ResourcePair(const ResourceRecord& a, std::span<const uint8_t> a_raw, const ResourceRecord& b,
               std::span<const uint8_t> b_raw);

  const ResourceRecord& a;
  const ResourceRecord& b;
  std::span<const uint8_t> a_raw, b_raw;

  // Same kind, byte count, and for images format and extent.
  bool same_shape() const { return same_shape_; }
  bool same_bytes() const;
  // Images of the same shape only.
  const DecodedImage& a_values() const;
  const DecodedImage& b_values() const;
  // For a metric that reads each value once, in order: visit(a, b, texels) gets one aspect's
  // values (aspect_channels floats per texel) of the next run of at most kBlockTexels texels of
  // both images, decoded then. The values stay in cache between decoding and use, and no decoded
  // copy of either whole image is made (a 1280x720 RGBA image's is 14 MiB). Images of the same
  // shape only.
  static constexpr uint64_t kBlockTexels = 1024;
  void for_each_block(uint32_t aspect, const std::function<void(const float*, const float*, uint64_t)>& visit) const;

 private:
  bool same_shape_ = false;
  mutable std::optional<DecodedImage> a_values_, b_values_;
};

}  // namespace nightcap
