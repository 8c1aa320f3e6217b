// FLIP, the perceptual difference between a reference image and a test image as an observer
// sees them flipped back and forth: LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator
// for Alternating Images", HPG 2020) and HDR-FLIP (Andersson et al., "Visualizing Errors in
// Rendered High Dynamic Range Images", Eurographics 2021), written from the papers.
#pragma once

#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

namespace nightcap {

// Pixels per degree of visual angle for an observer `distance_m` from a monitor `monitor_width_m`
// wide that shows `monitor_pixels` across; the paper's small-angle formula.
constexpr double flip_pixels_per_degree(double distance_m, double monitor_width_m, double monitor_pixels) {
  return distance_m * (monitor_pixels / monitor_width_m) * std::numbers::pi / 180.0;
}
// The papers' observer: 0.7 m from a 0.7 m wide monitor 3840 pixels across (≈ 67.02).
inline constexpr double kFlipDefaultPixelsPerDegree = flip_pixels_per_degree(0.7, 0.7, 3840.0);

// An image in linear RGB, not sRGB-encoded: texels of an _SRGB format come out of format.h's
// decode_texel linear already; display-encoded values stored in a UNORM image need
// srgb_to_linear (format.h) first. LDR-FLIP clamps to [0, 1], as a display would; HDR-FLIP
// clamps negative radiance to 0. Every value must be finite: both entry points throw
// std::invalid_argument naming the first NaN or infinity, because no error can be stated for
// such a pixel and its neighbourhood (the filters would spread it over up to 21 × 21 pixels).
struct FlipImage {
  uint32_t width = 0, height = 0;
  uint32_t channels = 3;          // interleaved per pixel: 3 (RGB) or 4 (RGBA, alpha ignored)
  std::span<const float> texels;  // width · height · channels, rows top to bottom
};

// An image handed over a row at a time, for callers that do not hold its floats whole (a
// displayed image decodes from a byte per channel as FLIP reads it). `row` writes row y's
// width · channels linear values, every one finite, to `out`; FLIP calls it from several
// threads, each row once, in increasing order within a band of rows.
struct FlipRows {
  uint32_t width = 0, height = 0;
  uint32_t channels = 3;  // 3 (RGB) or 4 (RGBA, alpha ignored)
  std::function<void(uint32_t y, float* out)> row;
};

struct FlipOptions {
  double pixels_per_degree = kFlipDefaultPixelsPerDegree;
  // over_threshold_share counts the pixels whose error exceeds this.
  float threshold = 0.1f;
  // LDR-FLIP only: also return the colour and feature errors the error is made of.
  bool keep_components = false;
  unsigned threads = 0;  // 0: one per hardware thread
};

struct FlipResult {
  uint32_t width = 0, height = 0;
  std::vector<float> error;  // per pixel, rows top to bottom, in [0, 1]
  // With keep_components: ΔE_c and ΔE_f of each pixel, error = ΔE_c^(1 − ΔE_f).
  std::vector<float> colour_error, feature_error;
  double mean = 0.0, max = 0.0;
  double median = 0.0, p95 = 0.0, p99 = 0.0;  // percentiles of the pixels' errors
  double over_threshold_share = 0.0;
};

FlipResult flip_ldr(const FlipImage& reference, const FlipImage& test, const FlipOptions& options = {});
// The same for images given by rows: their values are not checked (the caller vouches for them).
FlipResult flip_ldr(const FlipRows& reference, const FlipRows& test, const FlipOptions& options = {});

// The exposures (log2 scale factors on radiance) at which HDR-FLIP compares the tone-mapped
// images.
struct FlipExposures {
  double start = 0.0, stop = 0.0;
  uint32_t count = 1;  // start, stop and evenly spaced ones between
};
// The paper's range for `reference`: the start exposure maps its largest luminance, the stop
// exposure its median luminance, to 0.85 on the ACES curve; one exposure per stop between, two
// at least. An all-black reference gives the single exposure 0. Where the median is black (half
// the image or more), the paper's stop is infinite; the median of the non-black pixels takes its
// place.
FlipExposures flip_exposure_range(const FlipImage& reference);

// HDR-FLIP: the per-pixel maximum of LDR-FLIP over the ACES-tone-mapped images at each exposure
// of `exposures` (by default flip_exposure_range(reference)).
FlipResult flip_hdr(const FlipImage& reference, const FlipImage& test, const FlipOptions& options = {},
                    std::optional<FlipExposures> exposures = std::nullopt);

}  // namespace nightcap
