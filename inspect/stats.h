// Statistics of one subresource of an image, per channel: range, mean, a histogram, and the
// values that are not ordinary numbers (NaN, Inf, and denormals as the format stores them).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "captures/capture.h"
#include "inspect/decode.h"

namespace nightcap {

struct TexelRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;
};

struct ChannelStats {
  double min = 0.0, max = 0.0, mean = 0.0;  // over the finite values; 0 when there are none
  uint64_t finite = 0, nan = 0, inf = 0;
  uint64_t denormal = 0;  // subnormal in the stored encoding (half or float)
  // Finite values in equal bins from min to max (all in bin 0 when min == max).
  std::vector<uint64_t> histogram;
};

constexpr uint32_t kHistogramBins = 16;

// Aspects follow one another (depth's channel, then stencil's). `rect` is in texels of the
// subimage and must lie inside it.
std::vector<ChannelStats> image_stats(const ResourceRecord& record, std::span<const uint8_t> raw,
                                      const Subimage& subimage, const TexelRect& rect);

}  // namespace nightcap
