// FLIP as its papers define it (compare/flip.h). One file over 600 lines on purpose: the colour
// pipeline, the feature pipeline and their filters use the constants stated once at the top, and
// each SIMD form sits beside the scalar helper whose operations it repeats in the same order (the
// same bits), which a reader checks side by side.
#include "compare/flip.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "compare/simd_kernels.h"

namespace nightcap {
namespace {

// The constants below are the papers' (HPG 2020 for LDR-FLIP, Eurographics 2021 for HDR-FLIP),
// checked against the values of the authors' reference implementation (NVlabs/flip).

// Colour pipeline: the contrast sensitivity functions of the achromatic, red-green and
// blue-yellow channels as sums of two Gaussians a · sqrt(π/b) · exp(−π² x² / b), x in degrees.
struct CsfTerm {
  double a, b;
};
// A term with a = 0 is absent.
constexpr CsfTerm kCsfAchromatic[2] = {{1.0, 0.0047}, {0.0, 0.0}};
constexpr CsfTerm kCsfRedGreen[2] = {{1.0, 0.0053}, {0.0, 0.0}};
constexpr CsfTerm kCsfBlueYellow[2] = {{34.1, 0.04}, {13.5, 0.025}};
constexpr double kColourExponent = 0.7;    // q_c
constexpr double kRemapBreakShare = 0.4;   // p_c: the share of c_max mapped to p_t
constexpr double kRemapBreakValue = 0.95;  // p_t
// Feature pipeline: the observer's edge detector has 0.082° from peak to trough, two standard
// deviations. The feature exponent q_f is 0.5, hence the square root where it is applied.
constexpr double kFeatureWidthDegrees = 0.082;
// HDR-FLIP: Narkowicz's fit of the ACES curve, (k0 x² + k1 x) / (k3 x² + k4 x + k5), with its
// 0.6 pre-exposure folded into the coefficients; both ends of the exposure range are where the
// curve reaches 0.85.
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};
constexpr double kExposureToneTarget = 0.85;
constexpr double kLuminance[3] = {0.2126, 0.7152, 0.0722};

// sRGB primaries with the D65 white, as exact fractions.
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0},
};

using flip_kernels::colour_space;
using flip_kernels::ColourSpace;
using flip_kernels::Kernel;
using flip_kernels::PerceivedRow;

void lab_hunt(const float xyz[3], const ColourSpace& space, float out[3]);
float hyab(const float a[3], const float b[3]) {
  return std::abs(a[0] - b[0]) + std::sqrt((a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

ColourSpace make_colour_space() {
  ColourSpace s{};
  const auto& m = kRgbToXyz;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      // The inverse is the transposed cofactor matrix over the determinant.
      const int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
      s.to_rgb[r][c] = float((m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det);
      s.to_xyz[r][c] = float(m[r][c]);
    }
  for (int r = 0; r < 3; ++r) {
    const double white = m[r][0] + m[r][1] + m[r][2];
    s.white[r] = float(white);
    s.inverse_white[r] = float(1.0 / white);
  }
  float green[3], blue[3];
  const float green_xyz[3] = {s.to_xyz[0][1], s.to_xyz[1][1], s.to_xyz[2][1]};
  const float blue_xyz[3] = {s.to_xyz[0][2], s.to_xyz[1][2], s.to_xyz[2][2]};
  lab_hunt(green_xyz, s, green);
  lab_hunt(blue_xyz, s, blue);
  s.max_distance = float(std::pow(double(hyab(green, blue)), kColourExponent));
  return s;
}

void multiply(const float m[3][3], const float v[3], float out[3]) {
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
}

// t^(1/3) for t > 0 to float precision: a guess from the exponent bits, then two Halley steps
// (cubic convergence from a guess within 5 %). libm's cbrtf took a quarter of FLIP's time.
float cube_root(float t) {
  float y = std::bit_cast<float>(std::bit_cast<uint32_t>(t) / 3u + 709921077u);
  for (int step = 0; step < 2; ++step) {
    const float cube = y * y * y;
    y *= (cube + 2.0f * t) / (2.0f * cube + t);
  }
  return y;
}

// CIELAB, then Hunt's adjustment: chroma scaled by lightness (a, b) · 0.01 L, so that dark
// colours differ less in colour than bright ones. CIELAB's f(t) is taken less its 4/29, which
// cancels exactly in L = 116 f(Y) − 16 and in the differences: near black, f = t / (3δ²) + 4/29
// in float would lose the t that q_c = 0.7 later magnifies.
void lab_hunt(const float xyz[3], const ColourSpace& space, float out[3]) {
  constexpr float delta = 6.0f / 29.0f;
  float f[3];
  for (int i = 0; i < 3; ++i) {
    const float t = xyz[i] * space.inverse_white[i];
    f[i] = t > delta * delta * delta ? cube_root(t) - 4.0f / 29.0f : t / (3.0f * delta * delta);
  }
  const float lightness = 116.0f * f[1];
  out[0] = lightness;
  out[1] = 0.01f * lightness * 500.0f * (f[0] - f[1]);
  out[2] = 0.01f * lightness * 200.0f * (f[1] - f[2]);
}

// Pixels [begin, end) of the filtered opponent planes (Y/Y_n, a, b), in place: back to linear RGB,
// clamped to what the display shows, then to Hunt-adjusted L*a*b*. Eight pixels at a time, with
// the same operations in the same order as the scalar helpers (so the same bits): the multiplies
// of `multiply`, std::clamp's comparisons, lab_hunt's branch as a select of both sides.
[[gnu::always_inline]] inline void clamped_hunt_lab_body(float* lightness, float* a, float* b, size_t begin, size_t end,
                                                         const ColourSpace& space) {
  using Lanes = simd::Floats8;
  using Words = simd::Words8;
  constexpr float delta = 6.0f / 29.0f;
  size_t i = begin;
  for (; i + 8 <= end; i += 8) {
    Lanes ny, pa, pb;
    std::memcpy(&ny, lightness + i, sizeof ny);
    std::memcpy(&pa, a + i, sizeof pa);
    std::memcpy(&pb, b + i, sizeof pb);
    const Lanes xyz[3] = {(ny + pa / 500.0f) * space.white[0], ny * space.white[1],
                          (ny - pb / 200.0f) * space.white[2]};
    Lanes linear[3], clamped[3], f[3];
    for (int r = 0; r < 3; ++r) {
      const Lanes c = space.to_rgb[r][0] * xyz[0] + space.to_rgb[r][1] * xyz[1] + space.to_rgb[r][2] * xyz[2];
      linear[r] = c < 0.0f ? Lanes{} : (1.0f < c ? Lanes{} + 1.0f : c);
    }
    for (int r = 0; r < 3; ++r)
      clamped[r] = space.to_xyz[r][0] * linear[0] + space.to_xyz[r][1] * linear[1] + space.to_xyz[r][2] * linear[2];
    for (int c = 0; c < 3; ++c) {
      const Lanes t = clamped[c] * space.inverse_white[c];
      // cube_root's guess and Halley steps.
      Lanes y = (Lanes)((Words)t / 3u + 709921077u);
      for (int step = 0; step < 2; ++step) {
        const Lanes cube = y * y * y;
        y *= (cube + 2.0f * t) / (2.0f * cube + t);
      }
      f[c] = t > delta * delta * delta ? y - 4.0f / 29.0f : t / (3.0f * delta * delta);
    }
    const Lanes l = 116.0f * f[1];
    const Lanes out_a = 0.01f * l * 500.0f * (f[0] - f[1]), out_b = 0.01f * l * 200.0f * (f[1] - f[2]);
    std::memcpy(lightness + i, &l, sizeof l);
    std::memcpy(a + i, &out_a, sizeof out_a);
    std::memcpy(b + i, &out_b, sizeof out_b);
  }
  for (; i < end; ++i) {
    const float ny = lightness[i];
    const float normalised[3] = {ny + a[i] / 500.0f, ny, ny - b[i] / 200.0f};
    const float xyz[3] = {normalised[0] * space.white[0], normalised[1] * space.white[1],
                          normalised[2] * space.white[2]};
    float linear[3];
    multiply(space.to_rgb, xyz, linear);
    for (float& c : linear) c = std::clamp(c, 0.0f, 1.0f);
    float clamped_xyz[3], lab[3];
    multiply(space.to_xyz, linear, clamped_xyz);
    lab_hunt(clamped_xyz, space, lab);
    lightness[i] = lab[0];
    a[i] = lab[1];
    b[i] = lab[2];
  }
}
using ClampedHuntLabPaths = simd::Compiled<clamped_hunt_lab_body>;
constexpr auto& clamped_hunt_lab = ClampedHuntLabPaths::dispatch;

// Runs `rows_of(begin, end)` over [0, rows) split into contiguous bands, one per thread.
template <typename Rows>
void parallel_rows(uint32_t rows, unsigned threads, const Rows& rows_of) {
  threads = std::max(1u, std::min(threads, rows));
  std::vector<std::thread> workers;
  for (unsigned t = 1; t < threads; ++t)
    workers.emplace_back(
        [&, t] { rows_of(uint32_t(uint64_t(rows) * t / threads), uint32_t(uint64_t(rows) * (t + 1) / threads)); });
  rows_of(0u, uint32_t(rows / threads));
  for (std::thread& w : workers) w.join();
}

// The filters are most of FLIP's time: eight pixels at a time (compare/simd.h).
using Lanes = simd::Floats8;
constexpr uint32_t kLanes = sizeof(Lanes) / sizeof(float);

// dst[x..x+lanes) = Σ_k taps[k] · sources[k][x..], or Σ_k taps[k] · (sources[k][x..] − centre[x..])
// for a zero-sum kernel; added to what dst holds where `add`. The block sums in registers.
template <typename Vector, bool kZeroSum>
[[gnu::always_inline]] inline void weighted_block(const Kernel& kernel, const float* const* sources,
                                                  const float* centre, float* dst, uint32_t x, bool add) {
  Vector sum{}, origin{}, source;
  if (add) std::memcpy(&sum, dst + x, sizeof sum);
  if constexpr (kZeroSum) std::memcpy(&origin, centre + x, sizeof origin);
  for (size_t k = 0; k < kernel.taps.size(); ++k) {
    std::memcpy(&source, sources[k] + x, sizeof source);
    if constexpr (kZeroSum)
      sum += kernel.taps[k] * (source - origin);
    else
      sum += kernel.taps[k] * source;
  }
  std::memcpy(dst + x, &sum, sizeof sum);
}

// weighted_block on four blocks side by side, each pixel's sum the same operations in the same
// order: four independent chains of additions, where one block's waits out each addition's
// latency (three times slower). Written out: with the sums in an array of four, GCC kept them in
// memory, slower than one block.
template <typename Vector, bool kZeroSum>
[[gnu::always_inline]] inline void weighted_four_blocks(const Kernel& kernel, const float* const* sources,
                                                        const float* centre, float* dst, uint32_t x, bool add) {
  constexpr uint32_t kWidth = sizeof(Vector) / sizeof(float);
  Vector s0{}, s1{}, s2{}, s3{}, o0{}, o1{}, o2{}, o3{}, v0, v1, v2, v3;
  if (add) {
    std::memcpy(&s0, dst + x, sizeof s0);
    std::memcpy(&s1, dst + x + kWidth, sizeof s1);
    std::memcpy(&s2, dst + x + 2 * kWidth, sizeof s2);
    std::memcpy(&s3, dst + x + 3 * kWidth, sizeof s3);
  }
  if constexpr (kZeroSum) {
    std::memcpy(&o0, centre + x, sizeof o0);
    std::memcpy(&o1, centre + x + kWidth, sizeof o1);
    std::memcpy(&o2, centre + x + 2 * kWidth, sizeof o2);
    std::memcpy(&o3, centre + x + 3 * kWidth, sizeof o3);
  }
  for (size_t k = 0; k < kernel.taps.size(); ++k) {
    const float tap = kernel.taps[k], *source = sources[k] + x;
    std::memcpy(&v0, source, sizeof v0);
    std::memcpy(&v1, source + kWidth, sizeof v1);
    std::memcpy(&v2, source + 2 * kWidth, sizeof v2);
    std::memcpy(&v3, source + 3 * kWidth, sizeof v3);
    if constexpr (kZeroSum) {
      s0 += tap * (v0 - o0);
      s1 += tap * (v1 - o1);
      s2 += tap * (v2 - o2);
      s3 += tap * (v3 - o3);
    } else {
      s0 += tap * v0;
      s1 += tap * v1;
      s2 += tap * v2;
      s3 += tap * v3;
    }
  }
  std::memcpy(dst + x, &s0, sizeof s0);
  std::memcpy(dst + x + kWidth, &s1, sizeof s1);
  std::memcpy(dst + x + 2 * kWidth, &s2, sizeof s2);
  std::memcpy(dst + x + 3 * kWidth, &s3, sizeof s3);
}

template <bool kZeroSum>
[[gnu::always_inline]] inline void weighted_row(const Kernel& kernel, const float* const* sources, const float* centre,
                                                float* dst, uint32_t n, bool add) {
  uint32_t x = 0;
  for (; x + 8 * kLanes <= n; x += 8 * kLanes)
    weighted_four_blocks<simd::Floats16, kZeroSum>(kernel, sources, centre, dst, x, add);
  for (; x + 2 * kLanes <= n; x += 2 * kLanes)
    weighted_block<simd::Floats16, kZeroSum>(kernel, sources, centre, dst, x, add);
  for (; x + kLanes <= n; x += kLanes) weighted_block<Lanes, kZeroSum>(kernel, sources, centre, dst, x, add);
  for (; x < n; ++x) {
    float sum = add ? dst[x] : 0.0f;
    for (size_t k = 0; k < kernel.taps.size(); ++k)
      sum += kernel.taps[k] * (kZeroSum ? sources[k][x] - centre[x] : sources[k][x]);
    dst[x] = sum;
  }
}

// dst[x] = Σ_k taps[k] · sources[k][x] for x in [0, n), or Σ_k taps[k] · (sources[k][x] −
// centre[x]) for a zero-sum kernel; added to what dst holds where `add`. Sixty-four pixels at a
// time, as four blocks of sixteen (one AVX-512 register, two AVX2 ones), then sixteen, eight and
// one: each pixel's sum the same operations whatever the width.
[[gnu::always_inline]] inline void weighted_sum_body(const Kernel& kernel, const float* const* sources,
                                                     const float* centre, float* dst, uint32_t n, bool add) {
  if (kernel.zero_sum)
    weighted_row<true>(kernel, sources, centre, dst, n, add);
  else
    weighted_row<false>(kernel, sources, centre, dst, n, add);
}
using WeightedSumPaths = simd::Compiled<weighted_sum_body>;
constexpr auto& weighted_sum = WeightedSumPaths::dispatch;

// Vector arguments are passed by reference: by value, the paths' calling conventions would differ
// (GCC's -Wpsabi), even inlined.
[[gnu::always_inline]] inline void sqrt_lanes(Lanes& x) {
  for (uint32_t lane = 0; lane < kLanes; ++lane) x[lane] = std::sqrt(x[lane]);
}

// out[x] = √(u[x]² + v[x]²) for x in [0, n), eight at a time: each operation rounded once, as
// the scalar expression's are, so the same bits.
[[gnu::always_inline]] inline void magnitudes_body(const float* u, const float* v, float* out, uint32_t n) {
  uint32_t x = 0;
  for (; x + kLanes <= n; x += kLanes) {
    Lanes a, b;
    std::memcpy(&a, u + x, sizeof a);
    std::memcpy(&b, v + x, sizeof b);
    Lanes magnitude = a * a + b * b;
    sqrt_lanes(magnitude);
    std::memcpy(out + x, &magnitude, sizeof magnitude);
  }
  for (; x < n; ++x) out[x] = std::sqrt(u[x] * u[x] + v[x] * v[x]);
}
using MagnitudesPaths = simd::Compiled<magnitudes_body, simd::Path::avx2>;
constexpr auto& magnitudes = MagnitudesPaths::dispatch;

// A separable 2D kernel as a sum of products horizontal(x) · vertical(y).
struct SeparableTerm {
  Kernel horizontal, vertical;
};

// The CSF of one channel sampled at `radius` pixels either side, normalised to sum 1 so that a
// flat colour keeps its value. A 2D Gaussian is the product of two 1D ones, so each term is a
// normalised 1D Gaussian across times the same, scaled by the term's share of the sum, down.
std::vector<SeparableTerm> csf_kernel(const CsfTerm (&csf)[2], int radius, double pixels_per_degree) {
  std::vector<std::vector<double>> gaussians;  // normalised to sum 1
  std::vector<double> sums;                    // of each term's unnormalised 2D kernel
  double total = 0.0;
  for (const CsfTerm& t : csf) {
    if (t.a == 0.0) continue;
    std::vector<double> gaussian;
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
      const double degrees = i / pixels_per_degree;
      gaussian.push_back(std::exp(-std::numbers::pi * std::numbers::pi * degrees * degrees / t.b));
      sum += gaussian.back();
    }
    for (double& v : gaussian) v /= sum;
    gaussians.push_back(gaussian);
    sums.push_back(t.a * std::sqrt(std::numbers::pi / t.b) * sum * sum);
    total += sums.back();
  }
  std::vector<SeparableTerm> terms(gaussians.size());
  for (size_t i = 0; i < terms.size(); ++i)
    for (double v : gaussians[i]) {
      terms[i].horizontal.taps.push_back(float(v));
      terms[i].vertical.taps.push_back(float(v * sums[i] / total));
    }
  return terms;
}

// The paper's rule: three standard deviations of the widest Gaussian of the three CSFs.
int csf_radius(double pixels_per_degree) {
  double widest = 0.0;
  for (const auto* csf : {&kCsfAchromatic, &kCsfRedGreen, &kCsfBlueYellow})
    for (const CsfTerm& t : *csf) widest = std::max(widest, t.b);
  return int(std::ceil(3.0 * std::sqrt(widest / (2.0 * std::numbers::pi * std::numbers::pi)) * pixels_per_degree));
}

// The feature detectors: the first and second derivatives of a Gaussian, each scaled so that its
// positive taps sum to 1 and its negative ones to −1, along one axis, times the Gaussian
// (normalised to sum 1) along the other; the product is the paper's 2D normalisation.
struct FeatureKernels {
  Kernel gaussian, edge, point;
};
FeatureKernels feature_kernels(double pixels_per_degree) {
  const double sigma = 0.5 * kFeatureWidthDegrees * pixels_per_degree;
  const int radius = int(std::ceil(3.0 * sigma));
  std::vector<double> gaussian, edge, point;
  for (int x = -radius; x <= radius; ++x) {
    const double g = std::exp(-double(x) * x / (2.0 * sigma * sigma));
    gaussian.push_back(g);
    edge.push_back(-x * g);
    point.push_back((double(x) * x / (sigma * sigma) - 1.0) * g);
  }
  auto normalised = [](const std::vector<double>& taps, bool zero_sum) {
    double positive = 0.0, negative = 0.0;
    for (double v : taps) (v > 0 ? positive : negative) += v;
    Kernel k{{}, zero_sum};
    for (double v : taps) k.taps.push_back(float(v > 0 ? v / positive : (v < 0 ? -v / negative : 0.0)));
    return k;
  };
  return {normalised(gaussian, false), normalised(edge, true), normalised(point, true)};
}

void check_image(const FlipImage& image, const char* which) {
  if (image.channels != 3 && image.channels != 4)
    throw std::invalid_argument(std::string("flip: the ") + which + " image has " + std::to_string(image.channels) +
                                " channels; 3 or 4 expected");
  if (image.texels.size() != size_t(image.width) * image.height * image.channels)
    throw std::invalid_argument(std::string("flip: the ") + which + " image holds " +
                                std::to_string(image.texels.size()) + " values, not width · height · channels");
  for (size_t i = 0; i < image.texels.size(); ++i)
    if (!std::isfinite(image.texels[i])) {
      const size_t pixel = i / image.channels;
      throw std::invalid_argument(std::string("flip: the ") + which + " image is not finite at pixel (" +
                                  std::to_string(pixel % image.width) + ", " + std::to_string(pixel / image.width) +
                                  ")");
    }
}

void check_pair(const FlipImage& reference, const FlipImage& test) {
  check_image(reference, "reference");
  check_image(test, "test");
  if (reference.width != test.width || reference.height != test.height)
    throw std::invalid_argument("flip: the images differ in size");
}

// A checked image's rows, copied out as FLIP reads them.
FlipRows rows_of(const FlipImage& image) {
  return {image.width, image.height, image.channels, [&image](uint32_t y, float* out) {
            const size_t row = size_t(image.width) * image.channels;
            std::copy_n(image.texels.data() + y * row, row, out);
          }};
}

unsigned thread_count(const FlipOptions& options) {
  return options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
}

struct Filters {
  std::vector<SeparableTerm> achromatic, red_green, blue_yellow;
  FeatureKernels features;
  // The widest kernel's radius: how far the filters reach, along a row and up and down.
  int reach() const {
    int widest = std::max({features.gaussian.radius(), features.edge.radius(), features.point.radius()});
    for (const auto* csf : {&achromatic, &red_green, &blue_yellow})
      for (const SeparableTerm& t : *csf) widest = std::max({widest, t.horizontal.radius(), t.vertical.radius()});
    return widest;
  }
};

// A plane's rows filtered along the row, kept only while a column filter can reach them: row y
// in slot y mod (2·reach + 1), so the slots hold every row within reach of the one perceived.
class RowRing {
 public:
  RowRing(uint32_t width, int reach)
      : width_(width), slots_(2 * uint32_t(reach) + 1), values_(size_t(width) * slots_) {}
  float* row(uint32_t y) { return values_.data() + size_t(y % slots_) * width_; }
  const float* row(uint32_t y) const { return values_.data() + size_t(y % slots_) * width_; }

 private:
  uint32_t width_, slots_;
  std::vector<float> values_;
};

// One image as the observer perceives it, a row at a time down a band of rows. Each source row is
// converted and filtered along the row once, into rings that the column filters read; the whole
// pipeline's working set is a few dozen rows, where whole planes (sixteen of them for a pair)
// cost more in page faults and cache misses than in arithmetic. The filters' edges are clamped.
class Perception {
 public:
  // The image's values are clamped here to what the display shows.
  Perception(const Filters& filters, const FlipRows& image)
      : filters_(filters),
        image_(image),
        width_(image.width),
        height_(image.height),
        reach_(filters.reach()),
        source_(size_t(width_) * image.channels),
        smoothed_(width_, reach_),
        slope_(width_, reach_),
        curvature_(width_, reach_),
        lightness(width_),
        a(width_),
        b(width_),
        edges(width_),
        points(width_) {
    for (int c = 0; c < 3; ++c) {
      opponent_[c].resize(width_ + 2 * size_t(reach_));
      for (size_t t = 0; t < csf(c).size(); ++t) colour_rings_[c].emplace_back(width_, reach_);
    }
    for (std::vector<float>* row : {&edge_x_, &edge_y_, &point_x_, &point_y_}) row->resize(width_);
  }

  // Makes row y ready in the rows below. Rows come in increasing order.
  void perceive(uint32_t y) {
    if (!next_) next_ = uint32_t(std::max(0, int(y) - reach_));
    for (const uint32_t last = std::min(height_ - 1, y + uint32_t(reach_)); *next_ <= last; ++*next_)
      filter_along(*next_);
    float* colour[3] = {lightness.data(), a.data(), b.data()};
    for (int c = 0; c < 3; ++c)
      for (size_t t = 0; t < csf(c).size(); ++t)
        filter_column(colour_rings_[c][t], csf(c)[t].vertical, y, colour[c], t > 0);
    // Back to linear RGB to clamp what the filters pushed out of the displayable gamut, then on
    // to Hunt-adjusted L*a*b*, in place.
    clamped_hunt_lab(lightness.data(), a.data(), b.data(), 0, width_, colour_space());

    const FeatureKernels& k = filters_.features;
    filter_column(slope_, k.gaussian, y, edge_x_.data(), false);
    filter_column(smoothed_, k.edge, y, edge_y_.data(), false);
    filter_column(curvature_, k.gaussian, y, point_x_.data(), false);
    filter_column(smoothed_, k.point, y, point_y_.data(), false);
    magnitudes(edge_x_.data(), edge_y_.data(), edges.data(), width_);
    magnitudes(point_x_.data(), point_y_.data(), points.data(), width_);
  }

 private:
  const std::vector<SeparableTerm>& csf(int channel) const {
    return channel == 0 ? filters_.achromatic : channel == 1 ? filters_.red_green : filters_.blue_yellow;
  }

  // Source row y to the opponent space, then along the row through each filter into the rings.
  void filter_along(uint32_t y) {
    const ColourSpace& space = colour_space();
    // The opponent space YyCxCz: L*a*b* without the cube root, linear in XYZ so that filtering it
    // is filtering light. Its achromatic channel is kept as Y/Y_n = (Yy + 16) / 116, which the
    // normalised CSF filters the same way: in float, Yy's offset of −16 would drown the faint
    // light a bright pixel spreads over dark neighbours, which q_c = 0.7 then makes visible
    // (~1e-4).
    float* opponent[3] = {opponent_[0].data() + reach_, opponent_[1].data() + reach_, opponent_[2].data() + reach_};
    image_.row(y, source_.data());
    for (uint32_t x = 0; x < width_; ++x) {
      const float* texel = source_.data() + size_t(x) * image_.channels;
      const float displayed[3] = {std::clamp(texel[0], 0.0f, 1.0f), std::clamp(texel[1], 0.0f, 1.0f),
                                  std::clamp(texel[2], 0.0f, 1.0f)};
      float xyz[3];
      multiply(space.to_xyz, displayed, xyz);
      const float nx = xyz[0] * space.inverse_white[0], ny = xyz[1] * space.inverse_white[1],
                  nz = xyz[2] * space.inverse_white[2];
      opponent[0][x] = ny;
      opponent[1][x] = 500.0f * (nx - ny);
      opponent[2][x] = 200.0f * (ny - nz);
    }
    for (int c = 0; c < 3; ++c) {
      std::fill_n(opponent_[c].begin(), reach_, opponent[c][0]);
      std::fill_n(opponent_[c].end() - reach_, reach_, opponent[c][width_ - 1]);
      for (size_t t = 0; t < csf(c).size(); ++t)
        filter_row(opponent_[c], csf(c)[t].horizontal, colour_rings_[c][t].row(y));
    }
    // The feature pipeline's input is the same normalised achromatic channel, unfiltered.
    const FeatureKernels& k = filters_.features;
    filter_row(opponent_[0], k.gaussian, smoothed_.row(y));
    filter_row(opponent_[0], k.edge, slope_.row(y));
    filter_row(opponent_[0], k.point, curvature_.row(y));
  }

  // `padded` (a row with reach_ copies of its end values either side) convolved with `kernel`.
  void filter_row(const std::vector<float>& padded, const Kernel& kernel, float* dst) {
    const int r = kernel.radius();
    sources_.resize(kernel.taps.size());
    for (int k = 0; k <= 2 * r; ++k) sources_[k] = padded.data() + (reach_ - r + k);
    weighted_sum(kernel, sources_.data(), padded.data() + reach_, dst, width_, false);
  }

  // Row y of the plane whose rows `ring` holds, convolved down the columns with `kernel`, into
  // `dst` (added to what it holds where `add`).
  void filter_column(const RowRing& ring, const Kernel& kernel, uint32_t y, float* dst, bool add) {
    const int r = kernel.radius();
    sources_.resize(kernel.taps.size());
    for (int k = 0; k <= 2 * r; ++k) sources_[k] = ring.row(uint32_t(std::clamp(int(y) + k - r, 0, int(height_) - 1)));
    weighted_sum(kernel, sources_.data(), ring.row(y), dst, width_, add);
  }

  const Filters& filters_;
  const FlipRows& image_;
  uint32_t width_, height_;
  int reach_;
  std::optional<uint32_t> next_;  // the next source row to filter along
  std::vector<float> source_;     // the row image_ gave
  std::vector<float> opponent_[3];
  std::vector<RowRing> colour_rings_[3];  // one per CSF term
  RowRing smoothed_, slope_, curvature_;  // the achromatic channel through the feature kernels
  std::vector<float> edge_x_, edge_y_, point_x_, point_y_;
  std::vector<const float*> sources_;

 public:
  // Row y after perceive(y): colour after the CSFs in Hunt-adjusted L*a*b*, and the magnitudes
  // of its edges and points.
  std::vector<float> lightness, a, b, edges, points;

  PerceivedRow row() const { return {lightness.data(), a.data(), b.data(), edges.data(), points.data()}; }
};

// Lane-wise helpers of pixel_errors, inlined into each of its paths' functions (compare/simd.h).
using Words = simd::Words8;
using SignedWords = int32_t __attribute__((vector_size(32)));

// log2 of positive finite lanes: x = m · 2^e with m in [√½, √2), ln m = 2 atanh(s) with s = (m − 1)
// / (m + 1), |s| < 0.172, summed to s^9 (the next term is below 3e-9 of the first).
[[gnu::always_inline]] inline void log2_lanes(const Lanes& positive, Lanes& log2) {
  const SignedWords subnormal = positive < 0x1p-126f;
  const Lanes x = subnormal ? positive * 0x1p23f : positive;
  const Words bits = (Words)x;
  SignedWords exponent = (SignedWords)(bits >> 23) - 127 - (subnormal & 23);
  Lanes m = (Lanes)((bits & 0x7fffffu) | 0x3f800000u);
  const SignedWords halve = m > std::numbers::sqrt2_v<float>;
  m = halve ? m * 0.5f : m;
  exponent -= halve;  // halve is −1 where true
  const Lanes s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
  const Lanes ln_m = s * (2.0f + s2 * (2.0f / 3.0f + s2 * (2.0f / 5.0f + s2 * (2.0f / 7.0f + s2 * (2.0f / 9.0f)))));
  log2 = __builtin_convertvector(exponent, Lanes) + ln_m * std::numbers::log2e_v<float>;
}

// 2^y for lanes in [−150, 128]: y = n + f with n whole and |f| ≤ ½, 2^f = e^(f ln 2) by its Taylor
// series to degree 7 (relative error below 1e-8), times 2^n as two powers of two so that results
// below 2^−126 come out subnormal instead of wrong.
[[gnu::always_inline]] inline void exp2_lanes(const Lanes& exponent, Lanes& power_of_two) {
  const Lanes y = exponent < -150.0f ? Lanes{} - 150.0f : exponent;
  const Lanes whole = (y + 0x1.8p23f) - 0x1.8p23f;  // rounded to the nearest integer
  const Lanes z = (y - whole) * std::numbers::ln2_v<float>;
  const Lanes power =
      1.0f +
      z * (1.0f + z * (0.5f + z * (1.0f / 6 + z * (1.0f / 24 + z * (1.0f / 120 + z * (1.0f / 720 + z / 5040))))));
  const SignedWords n = __builtin_convertvector(whole, SignedWords), first = n >> 1, second = n - first;
  power_of_two = power * (Lanes)((Words)(first + 127) << 23) * (Lanes)((Words)(second + 127) << 23);
}

// base^exponent for base ≥ 0 and exponent in [0, 1], as std::pow: 0^0 = 1, 0^e = 0.
[[gnu::always_inline]] inline void pow_lanes(const Lanes& base, const Lanes& exponent, Lanes& power) {
  Lanes log2_base, raised;
  log2_lanes(base == 0.0f ? Lanes{} + 1.0f : base, log2_base);
  exp2_lanes(exponent * log2_base, raised);
  power = base == 0.0f ? (exponent == 0.0f ? Lanes{} + 1.0f : Lanes{}) : raised;
}

// FLIP of one row's pixels from both images' perceptions, eight at a time: colour error ΔE_c
// from HyAB^q_c remapped to [0, 1] (the lower p_c of c_max to [0, p_t], the rest to [p_t, 1], so
// that small differences spread over most of the scale), feature error ΔE_f, and
// ΔE_c^(1 − ΔE_f). The last pixels that do not fill eight lanes run padded through the same
// lanes, so a pixel's value does not depend on where in the row it is.
[[gnu::always_inline]] inline void pixel_errors_body(const PerceivedRow& r, const PerceivedRow& t, uint32_t width,
                                                     float max_distance, float* error, float* colour, float* feature) {
  const float knee = float(kRemapBreakShare) * max_distance;
  const float* planes[10] = {r.lightness, r.a, r.b, r.edges, r.points, t.lightness, t.a, t.b, t.edges, t.points};
  float padded[10][kLanes], padded_out[3][kLanes];
  for (uint32_t x = 0; x < width; x += kLanes) {
    const uint32_t n = std::min(kLanes, width - x);
    const float* in[10];
    float* out[3] = {error + x, colour ? colour + x : nullptr, feature ? feature + x : nullptr};
    for (int p = 0; p < 10; ++p) in[p] = planes[p] + x;
    if (n < kLanes) {
      for (int p = 0; p < 10; ++p) {
        std::fill(std::copy_n(in[p], n, padded[p]), padded[p] + kLanes, 0.0f);
        in[p] = padded[p];
      }
      for (int o = 0; o < 3; ++o) out[o] = out[o] ? padded_out[o] : nullptr;
    }
    Lanes v[10];
    for (int p = 0; p < 10; ++p) std::memcpy(&v[p], in[p], sizeof(Lanes));
    const Lanes dl = v[0] - v[5], da = v[1] - v[6], db = v[2] - v[7];
    Lanes chroma = da * da + db * db, distance;
    sqrt_lanes(chroma);
    pow_lanes((dl < 0.0f ? -dl : dl) + chroma, Lanes{} + float(kColourExponent), distance);  // HyAB^q_c
    const Lanes delta_c = distance < knee ? float(kRemapBreakValue) / knee * distance
                                          : float(kRemapBreakValue) + (distance - knee) / (max_distance - knee) *
                                                                          float(1.0 - kRemapBreakValue);
    const Lanes edge = v[3] - v[8], point = v[4] - v[9];
    const Lanes edge_difference = edge < 0.0f ? -edge : edge, point_difference = point < 0.0f ? -point : point;
    const Lanes feature_difference = edge_difference > point_difference ? edge_difference : point_difference;
    Lanes delta_f = feature_difference / std::numbers::sqrt2_v<float>, e;
    sqrt_lanes(delta_f);
    pow_lanes(delta_c, 1.0f - delta_f, e);
    std::memcpy(out[0], &e, sizeof e);
    if (out[1]) std::memcpy(out[1], &delta_c, sizeof delta_c);
    if (out[2]) std::memcpy(out[2], &delta_f, sizeof delta_f);
    if (n < kLanes) {
      std::copy_n(padded_out[0], n, error + x);
      if (colour) std::copy_n(padded_out[1], n, colour + x);
      if (feature) std::copy_n(padded_out[2], n, feature + x);
    }
  }
}
using PixelErrorsPaths = simd::Compiled<pixel_errors_body>;
constexpr auto& pixel_errors = PixelErrorsPaths::dispatch;

// LDR-FLIP's error map of two checked, clamped images, written into `result`. Each thread takes
// a band of rows and perceives both images down it, side by side.
class LdrFlip {
 public:
  LdrFlip(uint32_t w, uint32_t h, const FlipOptions& options) : threads_(thread_count(options)), width_(w), height_(h) {
    const double ppd = options.pixels_per_degree;
    const int radius = csf_radius(ppd);
    filters_ = {csf_kernel(kCsfAchromatic, radius, ppd), csf_kernel(kCsfRedGreen, radius, ppd),
                csf_kernel(kCsfBlueYellow, radius, ppd), feature_kernels(ppd)};
  }

  // error[i] = FLIP of pixel i; colour and feature receive ΔE_c and ΔE_f where not null.
  void run(const FlipRows& reference, const FlipRows& test, float* error, float* colour, float* feature) const {
    const float max_distance = colour_space().max_distance;
    parallel_rows(height_, threads_, [&](uint32_t begin, uint32_t end) {
      Perception seen_reference(filters_, reference), seen_test(filters_, test);
      for (uint32_t y = begin; y < end; ++y) {
        seen_reference.perceive(y);
        seen_test.perceive(y);
        const size_t row = size_t(y) * width_;
        pixel_errors(seen_reference.row(), seen_test.row(), width_, max_distance, error + row,
                     colour ? colour + row : nullptr, feature ? feature + row : nullptr);
      }
    });
  }

 private:
  unsigned threads_;
  uint32_t width_, height_;
  Filters filters_;
};

void summarise(FlipResult& result, float threshold) {
  const std::vector<float>& e = result.error;
  if (e.empty()) return;
  double sum = 0.0;
  size_t over = 0;
  float max = 0.0f;
  for (float v : e) {
    sum += v;
    over += v > threshold;
    max = std::max(max, v);
  }
  result.mean = sum / double(e.size());
  result.max = max;
  result.over_threshold_share = double(over) / double(e.size());
  std::vector<float> order = e;
  auto percentile = [&](double share, size_t from) {
    const size_t at = std::min(order.size() - 1, size_t(share * double(order.size() - 1) + 0.5));
    std::nth_element(order.begin() + from, order.begin() + at, order.end());
    return at;
  };
  // Each nth_element leaves the larger values after its pivot, so the next searches only those.
  const size_t median = percentile(0.5, 0);
  result.median = order[median];
  const size_t p95 = percentile(0.95, median);
  result.p95 = order[p95];
  result.p99 = order[percentile(0.99, p95)];
}

double aces(double x) {
  const double numerator = kAces[0] * x * x + kAces[1] * x + kAces[2];
  const double denominator = kAces[3] * x * x + kAces[4] * x + kAces[5];
  return std::clamp(numerator / denominator, 0.0, 1.0);
}

// The radiance that the ACES curve maps to `tone`: the positive root of
// (k0 − t k3) x² + (k1 − t k4) x + (k2 − t k5) = 0.
double aces_inverse(double tone) {
  const double c0 = (kAces[1] - tone * kAces[4]) / (kAces[0] - tone * kAces[3]);
  const double c1 = (kAces[2] - tone * kAces[5]) / (kAces[0] - tone * kAces[3]);
  return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

}  // namespace

const flip_kernels::ColourSpace& flip_kernels::colour_space() {
  static const ColourSpace space = make_colour_space();
  return space;
}

flip_kernels::Functions flip_kernels::compiled_for(simd::Path path) {
  return {ClampedHuntLabPaths::on(path), WeightedSumPaths::on(path), MagnitudesPaths::on(path),
          PixelErrorsPaths::on(path)};
}

FlipResult flip_ldr(const FlipImage& reference, const FlipImage& test, const FlipOptions& options) {
  check_pair(reference, test);
  return flip_ldr(rows_of(reference), rows_of(test), options);
}

FlipResult flip_ldr(const FlipRows& reference, const FlipRows& test, const FlipOptions& options) {
  for (const FlipRows* image : {&reference, &test})
    if ((image->channels != 3 && image->channels != 4) || !image->row)
      throw std::invalid_argument("flip: an image by rows needs 3 or 4 channels and a row function");
  if (reference.width != test.width || reference.height != test.height)
    throw std::invalid_argument("flip: the images differ in size");
  FlipResult result;
  result.width = reference.width;
  result.height = reference.height;
  const size_t pixels = size_t(reference.width) * reference.height;
  if (pixels == 0) return result;
  result.error.resize(pixels);
  if (options.keep_components) {
    result.colour_error.resize(pixels);
    result.feature_error.resize(pixels);
  }
  LdrFlip flip(reference.width, reference.height, options);
  flip.run(reference, test, result.error.data(), options.keep_components ? result.colour_error.data() : nullptr,
           options.keep_components ? result.feature_error.data() : nullptr);
  summarise(result, options.threshold);
  return result;
}

FlipExposures flip_exposure_range(const FlipImage& reference) {
  check_image(reference, "reference");
  std::vector<double> luminance;
  luminance.reserve(size_t(reference.width) * reference.height);
  for (size_t p = 0; p < reference.texels.size(); p += reference.channels) {
    double y = 0.0;
    for (int c = 0; c < 3; ++c) y += kLuminance[c] * std::max(0.0f, reference.texels[p + c]);
    luminance.push_back(y);
  }
  const double brightest = luminance.empty() ? 0.0 : *std::max_element(luminance.begin(), luminance.end());
  if (brightest == 0.0) return {};
  auto median_of = [](std::vector<double>& values, size_t from) {
    // As numpy's 50th percentile: the mean of the two middle values of an even count.
    const size_t n = values.size() - from, middle = from + n / 2;
    std::nth_element(values.begin() + from, values.begin() + middle, values.end());
    const double upper = values[middle];
    if (n % 2) return upper;
    return 0.5 * (upper + *std::max_element(values.begin() + from, values.begin() + middle));
  };
  double median = median_of(luminance, 0);
  if (median == 0.0) {
    const auto black_end = std::partition(luminance.begin(), luminance.end(), [](double y) { return y == 0.0; });
    median = median_of(luminance, size_t(black_end - luminance.begin()));
  }
  const double tone_radiance = aces_inverse(kExposureToneTarget);
  FlipExposures range;
  range.start = std::log2(tone_radiance / brightest);
  range.stop = std::log2(tone_radiance / median);
  range.count = range.start == range.stop ? 1u : uint32_t(std::max(2.0, std::ceil(range.stop - range.start)));
  return range;
}

FlipResult flip_hdr(const FlipImage& reference, const FlipImage& test, const FlipOptions& options,
                    std::optional<FlipExposures> exposures) {
  check_pair(reference, test);
  const FlipExposures range = exposures ? *exposures : flip_exposure_range(reference);
  if (range.count == 0 || range.stop < range.start)
    throw std::invalid_argument("flip: the exposure range is empty or runs backwards");
  FlipResult result;
  result.width = reference.width;
  result.height = reference.height;
  const size_t pixels = size_t(reference.width) * reference.height;
  if (pixels == 0) return result;
  result.error.assign(pixels, 0.0f);
  LdrFlip flip(reference.width, reference.height, options);
  std::vector<float> error(pixels);
  for (uint32_t e = 0; e < range.count; ++e) {
    const double exposure = range.start + e * (range.stop - range.start) / std::max(1u, range.count - 1);
    const double scale = std::exp2(exposure);
    // Each image tone-mapped at this exposure, row by row as LDR-FLIP reads it.
    auto tone_mapped = [&](const FlipImage& image) {
      return FlipRows{image.width, image.height, 3, [&image, scale](uint32_t y, float* out) {
                        const float* texels = image.texels.data() + size_t(y) * image.width * image.channels;
                        for (uint32_t x = 0; x < image.width; ++x)
                          for (uint32_t c = 0; c < 3; ++c)
                            out[x * 3 + c] = float(aces(scale * std::max(0.0f, texels[x * image.channels + c])));
                      }};
    };
    flip.run(tone_mapped(reference), tone_mapped(test), error.data(), nullptr, nullptr);
    for (size_t p = 0; p < pixels; ++p) result.error[p] = std::max(result.error[p], error[p]);
  }
  summarise(result, options.threshold);
  return result;
}

}  // namespace nightcap
