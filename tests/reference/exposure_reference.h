// A CPU double-precision reference for exposure, shared by its unit test and the end-to-end test
// over recorded frames. Written from what the pass documents, not from its shader: Rec. 709
// luminance of each texel as the GPU decodes it, 256 bins of log2 luminance over
// [log2_min, log2_max) (NaN not counted, +Inf in the top bin, at or below 2^log2_min in the
// bottom one), the mean at the bin centres, exponential adaptation and Krawczyk et al.'s key.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "passes/post/exposure.glsl.h"

namespace nightcap::reference {

struct ExposureHistogram {
  std::vector<uint64_t> bins = std::vector<uint64_t>(kExposureBins, 0);
  uint64_t counted = 0;     // pixels with a luminance (not NaN)
  uint64_t near_edges = 0;  // pixels whose bin the GPU's log2 may legitimately choose one off
  double measured = 0;      // mean log2 luminance at the bin centres
};

inline ExposureHistogram exposure_histogram(const std::vector<std::array<double, 3>>& rgb, double log2_min,
                                            double log2_max) {
  ExposureHistogram h;
  for (const auto& [r, g, b] : rgb) {
    const double l = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    if (std::isnan(l)) continue;
    size_t bin = 0;
    if (std::isinf(l) && l > 0) {
      bin = kExposureBins - 1;
    } else if (l > std::exp2(log2_min)) {
      const double t = (std::log2(l) - log2_min) / (log2_max - log2_min) * kExposureBins;
      bin = size_t(std::clamp(std::floor(t), 0.0, double(kExposureBins - 1)));
      if (std::abs(t - std::round(t)) < 1e-4) ++h.near_edges;
    }
    ++h.bins[bin];
    ++h.counted;
  }
  const double width = (log2_max - log2_min) / kExposureBins;
  double sum = 0;
  for (size_t i = 0; i < kExposureBins; ++i) sum += double(h.bins[i]) * (log2_min + (i + 0.5) * width);
  h.measured = sum / double(h.counted);
  return h;
}

// The adapted log2 luminance after `seconds` from `previous` toward `measured` (time constant
// `tau`; 0: instant).
inline double adapt_exposure(double measured, double previous, double seconds, double tau) {
  const double keep = tau > 0 ? std::exp(-seconds / tau) : 0.0;
  return measured + (previous - measured) * keep;
}

// Krawczyk, Myszkowski and Seidel 2005: the key for a scene of mean luminance `mean`.
inline double automatic_key(double mean) { return 1.03 - 2.0 / (2.0 + std::log10(mean + 1.0)); }

}  // namespace nightcap::reference
