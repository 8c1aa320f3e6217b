#include "inspect/stats.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace nightcap {

namespace {

// A stored half or float with a zero exponent and a non-zero mantissa. Read from the stored
// bits: a half denormal is an ordinary float once decoded.
bool stored_denormal(ChannelEncoding encoding, std::span<const uint8_t> plane, uint64_t offset) {
  if (encoding == ChannelEncoding::sfloat16) {
    uint16_t bits;
    std::memcpy(&bits, plane.data() + offset, 2);
    return (bits & 0x7c00) == 0 && (bits & 0x03ff) != 0;
  }
  if (encoding == ChannelEncoding::sfloat32 || encoding == ChannelEncoding::depth32_stencil8) {
    float value;
    std::memcpy(&value, plane.data() + offset, 4);
    return std::fpclassify(value) == FP_SUBNORMAL;
  }
  return false;
}

}  // namespace

std::vector<ChannelStats> image_stats(const ResourceRecord& record, std::span<const uint8_t> raw,
                                      const Subimage& subimage, const TexelRect& rect) {
  const FormatInfo format = *format_info(record.format);
  const uint32_t mip = subimage.mip, layer = subimage.layer;
  const uint32_t width = mip_size(record.extent.width, mip);
  const uint64_t first_row = uint64_t(subimage.slice) * mip_size(record.extent.height, mip);
  std::vector<ChannelStats> result;
  for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect) {
    const std::span<const uint8_t> plane =
        raw.subspan(raw_subresource_offset(format, record.extent, aspect, mip, layer),
                    raw_subresource_bytes(format, record.extent, aspect, mip));
    const uint32_t channels = aspect_channels(format, aspect), texel_bytes = aspect_texel_bytes(format, aspect);
    // Float channels are evenly spaced in the texel; the denormal test needs each one's offset.
    const uint32_t channel_bytes = format.encoding == ChannelEncoding::sfloat16 ? 2 : 4;
    std::vector<std::vector<double>> values(channels);
    std::vector<ChannelStats> stats(channels);
    for (uint32_t y = rect.y; y < rect.y + rect.height; ++y)
      for (uint32_t x = rect.x; x < rect.x + rect.width; ++x) {
        const uint64_t index = (first_row + y) * width + x;
        float texel[4] = {};
        decode_texel(format, aspect, plane, index, texel);
        for (uint32_t c = 0; c < channels; ++c) {
          ChannelStats& s = stats[c];
          if (std::isnan(texel[c])) {
            ++s.nan;
          } else if (std::isinf(texel[c])) {
            ++s.inf;
          } else {
            values[c].push_back(texel[c]);
          }
          if (aspect == 0 && stored_denormal(format.encoding, plane, index * texel_bytes + c * channel_bytes))
            ++s.denormal;
        }
      }
    for (uint32_t c = 0; c < channels; ++c) {
      ChannelStats& s = stats[c];
      s.histogram.assign(kHistogramBins, 0);
      s.finite = values[c].size();
      if (values[c].empty()) continue;
      const auto [lo, hi] = std::minmax_element(values[c].begin(), values[c].end());
      s.min = *lo;
      s.max = *hi;
      double sum = 0.0;
      for (double v : values[c]) sum += v;
      s.mean = sum / double(values[c].size());
      const double span = s.max - s.min;
      for (double v : values[c]) {
        const size_t bin =
            span > 0.0 ? std::min<size_t>(kHistogramBins - 1, size_t((v - s.min) / span * kHistogramBins)) : 0;
        ++s.histogram[bin];
      }
    }
    result.insert(result.end(), stats.begin(), stats.end());
  }
  return result;
}

}  // namespace nightcap
