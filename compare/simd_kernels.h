// The diff's SIMD loops (compare/simd.h), a path's functions at a time: the program calls them
// through their dispatchers, which run the widest path the CPU has; tests call every path the CPU
// has through these tables and hold each to the generic path's bits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "compare/simd.h"
#include "passes/core/contract.h"

#include <vector>

namespace nightcap::flip_kernels {

struct ColourSpace {
  float to_xyz[3][3], to_rgb[3][3];
  float inverse_white[3];  // 1 / (X_n, Y_n, Z_n): the white is what RGB (1, 1, 1) maps to
  float white[3];
  float max_distance;  // c_max: green to blue, the farthest colours of the gamut, to the power q_c
};

// sRGB with the D65 white, FLIP's colour space.
const ColourSpace& colour_space();

// A 1D kernel of 2·radius + 1 taps, centre at index radius. A zero-sum kernel (a derivative of
// a Gaussian) is applied to differences from the centre pixel: the same sum in exact arithmetic,
// but exactly 0 on flat regions, where rounding would otherwise leave ~1e-8 that the feature
// pipeline's square root turns into a visible 1e-4.
struct Kernel {
  std::vector<float> taps;
  bool zero_sum = false;
  int radius() const { return int(taps.size() / 2); }
};

// One row of what FLIP perceives of an image: colour after the CSFs in Hunt-adjusted L*a*b*, and
// the magnitudes of its edges and points.
struct PerceivedRow {
  const float *lightness, *a, *b, *edges, *points;
};

struct Functions {
  // Pixels [begin, end) of the filtered opponent planes (Y/Y_n, a, b), in place: to linear RGB,
  // clamped to what the display shows, then to Hunt-adjusted L*a*b*.
  void (*clamped_hunt_lab)(float* lightness, float* a, float* b, size_t begin, size_t end, const ColourSpace& space);
  // dst[x] = Σ_k taps[k] · sources[k][x] for x in [0, n), or Σ_k taps[k] · (sources[k][x] −
  // centre[x]) for a zero-sum kernel; added to what dst holds where `add`.
  void (*weighted_sum)(const Kernel& kernel, const float* const* sources, const float* centre, float* dst, uint32_t n,
                       bool add);
  // out[x] = √(u[x]² + v[x]²) for x in [0, n).
  void (*magnitudes)(const float* u, const float* v, float* out, uint32_t n);
  // FLIP of one row's `width` pixels into error, and its colour and feature errors into `colour`
  // and `feature` where not null.
  void (*pixel_errors)(const PerceivedRow& reference, const PerceivedRow& test, uint32_t width, float max_distance,
                       float* error, float* colour, float* feature);
};

Functions compiled_for(simd::Path path);

}  // namespace nightcap::flip_kernels

namespace nightcap::decode_kernels {

struct Functions {
  // n little-endian halves to floats, half_to_float's value for each (a NaN a NaN with its payload).
  void (*halves_to_floats)(const uint8_t* halves, float* out, uint64_t n);
};

Functions compiled_for(simd::Path path);

}  // namespace nightcap::decode_kernels

namespace nightcap::metrics_kernels {

// What compare_resource sums over an image's texels, block by block.
struct ImageTally {
  double peak = 0.0;  // largest |a| of a float image (PSNR's peak), else 1
  double max_abs = 0.0, sum_squares = 0.0, angle_sum = 0.0;
  uint64_t values = 0, texels = 0, differing = 0, over = 0;
};

struct Functions {
  // A block of at most ResourcePair::kBlockTexels texels of finite values into `t`: the largest
  // difference, sum of squares and peak, texels that differ and that differ by more than the
  // threshold (relative: 1e-3 · max(1, |a|), else `fixed`); with `departs`, also the largest
  // departure from that float contract into `worst`. False, `t` and `worst` untouched, where a
  // value of either side is NaN or infinite.
  bool (*tally_finite)(const float* a, const float* b, uint64_t texels, uint32_t channels, bool relative, double fixed,
                       const ComparisonContract* departs, ImageTally& t, double& worst);
  // The largest |b − a| / (absolute + relative |a|) of a float contract over n values into
  // `worst`; false, `worst` untouched, where a value is NaN or infinite.
  bool (*worst_departure_finite)(const float* a, const float* b, uint64_t n, const ComparisonContract& contract,
                                 double& worst);
  // The largest |a[i] − b[i]| of two byte arrays.
  uint8_t (*largest_byte_difference)(const uint8_t* a, const uint8_t* b, size_t n);
};

Functions compiled_for(simd::Path path);

}  // namespace nightcap::metrics_kernels
