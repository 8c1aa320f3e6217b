// FLIP against the papers' formulas written out again here in double precision: a plain 2D
// (not separable) implementation for small images, and closed forms where the papers give them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "compare/flip.h"
#include "compare/flip_map.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

using Rgb = std::array<double, 3>;
constexpr double kPi = std::numbers::pi;
constexpr double kPpd = 3840.0 * kPi / 180.0;  // 0.7 m from a 0.7 m wide, 3840-pixel monitor

// sRGB (D65) to XYZ.
constexpr double kToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0},
};

Rgb apply(const double m[3][3], const Rgb& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

const Rgb& white() {
  static const Rgb w = apply(kToXyz, {1.0, 1.0, 1.0});
  return w;
}

// XYZ to sRGB by Cramer's rule.
Rgb to_rgb(const Rgb& xyz) {
  const auto& m = kToXyz;
  auto det = [](const Rgb& c0, const Rgb& c1, const Rgb& c2) {
    return c0[0] * (c1[1] * c2[2] - c2[1] * c1[2]) - c1[0] * (c0[1] * c2[2] - c2[1] * c0[2]) +
           c2[0] * (c0[1] * c1[2] - c1[1] * c0[2]);
  };
  const Rgb col0 = {m[0][0], m[1][0], m[2][0]}, col1 = {m[0][1], m[1][1], m[2][1]}, col2 = {m[0][2], m[1][2], m[2][2]};
  const double d = det(col0, col1, col2);
  return {det(xyz, col1, col2) / d, det(col0, xyz, col2) / d, det(col0, col1, xyz) / d};
}

Rgb to_ycxcz(const Rgb& rgb) {
  const Rgb xyz = apply(kToXyz, rgb);
  const double x = xyz[0] / white()[0], y = xyz[1] / white()[1], z = xyz[2] / white()[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Rgb ycxcz_to_rgb(const Rgb& o) {
  const double y = (o[0] + 16.0) / 116.0;
  return to_rgb({(y + o[1] / 500.0) * white()[0], y * white()[1], (y - o[2] / 200.0) * white()[2]});
}

// Hunt-adjusted CIELAB of a linear RGB colour.
Rgb hunt_lab(const Rgb& rgb) {
  const Rgb xyz = apply(kToXyz, rgb);
  auto f = [](double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / white()[0]), fy = f(xyz[1] / white()[1]), fz = f(xyz[2] / white()[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Rgb& a, const Rgb& b) { return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }

// ΔE_c of two displayed (clamped, linear) colours.
double colour_error(const Rgb& reference, const Rgb& test) {
  const double cmax = std::pow(hyab(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), 0.7);
  const double e = std::pow(hyab(hunt_lab(reference), hunt_lab(test)), 0.7);
  const double pc = 0.4, pt = 0.95;
  return e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
}

// A kernel of (2r + 1)² taps, k[(j + r) * (2r + 1) + i + r] weighs the pixel at offset (i, j).
struct Kernel2d {
  int r = 0;
  std::vector<double> k;
  double at(int i, int j) const { return k[(j + r) * (2 * r + 1) + i + r]; }
};

Kernel2d make_kernel(int r, const std::function<double(int, int)>& f) {
  Kernel2d out{r, {}};
  for (int j = -r; j <= r; ++j)
    for (int i = -r; i <= r; ++i) out.k.push_back(f(i, j));
  return out;
}

// The CSF of the paper, a1 sqrt(π/b1) exp(−π² d²/b1) + a2 sqrt(π/b2) exp(−π² d²/b2) with d in
// degrees, normalised to sum 1; the radius is 3 standard deviations of the widest, b = 0.04.
Kernel2d csf(double a1, double b1, double a2, double b2) {
  const int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * kPpd));
  Kernel2d k = make_kernel(r, [&](int i, int j) {
    const double d2 = (i * i + j * j) / (kPpd * kPpd);
    return a1 * std::sqrt(kPi / b1) * std::exp(-kPi * kPi * d2 / b1) +
           (a2 == 0.0 ? 0.0 : a2 * std::sqrt(kPi / b2) * std::exp(-kPi * kPi * d2 / b2));
  });
  double sum = 0.0;
  for (double v : k.k) sum += v;
  for (double& v : k.k) v /= sum;
  return k;
}

double feature_sigma() { return 0.5 * 0.082 * kPpd; }

// The edge (first derivative) or point (second derivative) detector along x, its positive
// weights scaled to sum 1 and its negative ones to −1.
Kernel2d detector(bool edge) {
  const double s = feature_sigma();
  Kernel2d k = make_kernel(int(std::ceil(3.0 * s)), [&](int i, int j) {
    const double g = std::exp(-(i * i + j * j) / (2.0 * s * s));
    return edge ? -i * g : (i * i / (s * s) - 1.0) * g;
  });
  double positive = 0.0, negative = 0.0;
  for (double v : k.k) (v > 0 ? positive : negative) += v;
  for (double& v : k.k) v = v > 0 ? v / positive : (v < 0 ? -v / negative : 0.0);
  return k;
}

Kernel2d transposed(const Kernel2d& k) {
  return make_kernel(k.r, [&](int i, int j) { return k.at(j, i); });
}

struct Image {
  int w = 0, h = 0;
  std::vector<float> rgb;  // 3 per pixel
  Rgb at(int x, int y) const {
    x = std::clamp(x, 0, w - 1);
    y = std::clamp(y, 0, h - 1);
    const float* p = &rgb[(size_t(y) * w + x) * 3];
    return {p[0], p[1], p[2]};
  }
  FlipImage view() const { return {uint32_t(w), uint32_t(h), 3, rgb}; }
};

Image constant(int w, int h, const Rgb& c) {
  Image im{w, h, {}};
  for (int i = 0; i < w * h; ++i)
    for (double v : c) im.rgb.push_back(float(v));
  return im;
}

// Correlation with edges clamped, as the paper's filtering.
double correlate(const Kernel2d& k, int x, int y, const std::function<double(int, int)>& value) {
  double sum = 0.0;
  for (int j = -k.r; j <= k.r; ++j)
    for (int i = -k.r; i <= k.r; ++i) sum += k.at(i, j) * value(x + i, y + j);
  return sum;
}

struct Errors {
  std::vector<double> error, colour, feature;
};

// LDR-FLIP of the paper, pixel by pixel with 2D kernels.
Errors reference_flip(const Image& reference, const Image& test) {
  const Kernel2d csfs[3] = {csf(1.0, 0.0047, 0.0, 0.0), csf(1.0, 0.0053, 0.0, 0.0), csf(34.1, 0.04, 13.5, 0.025)};
  const Kernel2d edge_x = detector(true), point_x = detector(false);
  const Kernel2d edge_y = transposed(edge_x), point_y = transposed(point_x);
  Errors out;
  for (int y = 0; y < reference.h; ++y)
    for (int x = 0; x < reference.w; ++x) {
      Rgb lab[2];
      double edges[2], points[2];
      for (int which = 0; which < 2; ++which) {
        const Image& im = which ? test : reference;
        Rgb filtered;
        for (int c = 0; c < 3; ++c)
          filtered[c] = correlate(csfs[c], x, y, [&](int px, int py) { return to_ycxcz(im.at(px, py))[c]; });
        Rgb rgb = ycxcz_to_rgb(filtered);
        for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
        lab[which] = hunt_lab(rgb);
        auto achromatic = [&](int px, int py) { return (to_ycxcz(im.at(px, py))[0] + 16.0) / 116.0; };
        edges[which] = std::hypot(correlate(edge_x, x, y, achromatic), correlate(edge_y, x, y, achromatic));
        points[which] = std::hypot(correlate(point_x, x, y, achromatic), correlate(point_y, x, y, achromatic));
      }
      const double cmax = std::pow(hyab(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), 0.7);
      const double e = std::pow(hyab(lab[0], lab[1]), 0.7);
      const double delta_c = e < 0.4 * cmax ? 0.95 / (0.4 * cmax) * e : 0.95 + (e - 0.4 * cmax) / (0.6 * cmax) * 0.05;
      const double delta_f =
          std::sqrt(std::max(std::abs(edges[0] - edges[1]), std::abs(points[0] - points[1])) / std::sqrt(2.0));
      out.colour.push_back(delta_c);
      out.feature.push_back(delta_f);
      out.error.push_back(std::pow(delta_c, 1.0 - delta_f));
    }
  return out;
}

FlipOptions with_components() {
  FlipOptions o;
  o.keep_components = true;
  return o;
}

TEST(Flip, DefaultObserverIsThePapers) {
  EXPECT_NEAR(kFlipDefaultPixelsPerDegree, 67.0206, 1e-4);
  EXPECT_DOUBLE_EQ(flip_pixels_per_degree(0.7, 0.7, 3840.0), kPpd);
}

TEST(Flip, IdenticalImagesHaveNoError) {
  Image im{37, 23, {}};
  for (int i = 0; i < im.w * im.h * 3; ++i) im.rgb.push_back(float((i * 7919) % 1000) / 999.0f);
  const FlipResult r = flip_ldr(im.view(), im.view());
  ASSERT_EQ(r.error.size(), size_t(im.w * im.h));
  for (float e : r.error) ASSERT_EQ(e, 0.0f);
  EXPECT_EQ(r.mean, 0.0);
  EXPECT_EQ(r.max, 0.0);
  EXPECT_EQ(r.over_threshold_share, 0.0);
  for (float e : flip_hdr(im.view(), im.view()).error) ASSERT_EQ(e, 0.0f);
}

// A flat image has no features and the normalised CSFs leave its colour as it is, so FLIP is the
// colour pipeline's value of the two colours alone.
TEST(Flip, ConstantImagesGiveTheColourPipelinesValue) {
  const std::array<std::pair<Rgb, Rgb>, 4> pairs = {{
      {{0.5, 0.5, 0.5}, {0.52, 0.52, 0.52}},
      {{0.18, 0.18, 0.18}, {0.1, 0.1, 0.1}},
      {{0.8, 0.1, 0.05}, {0.1, 0.6, 0.9}},
      {{0.05, 0.7, 0.2}, {0.6, 0.05, 0.5}},
  }};
  for (const auto& [a, b] : pairs) {
    const double expected = colour_error(a, b);
    const FlipResult r = flip_ldr(constant(40, 30, a).view(), constant(40, 30, b).view(), with_components());
    for (size_t i = 0; i < r.error.size(); ++i) {
      ASSERT_EQ(r.feature_error[i], 0.0f) << i;
      ASSERT_NEAR(r.error[i], expected, 2e-5) << a[0] << " vs " << b[0] << " at " << i;
    }
    EXPECT_NEAR(r.mean, expected, 2e-5);
    EXPECT_NEAR(r.median, expected, 2e-5);
    EXPECT_NEAR(r.max, expected, 2e-5);
  }
  // c_max is the distance of green to blue, so those two are the top of the scale.
  const FlipResult r = flip_ldr(constant(8, 8, {0, 1, 0}).view(), constant(8, 8, {0, 0, 1}).view());
  EXPECT_NEAR(r.max, 1.0, 1e-5);
}

TEST(Flip, StepEdgeMatchesThePapersFilters) {
  // Reference: black left of column 32, white from it on; test: black.
  const int w = 64, h = 4, step = 32;
  Image reference = constant(w, h, {0, 0, 0});
  for (int y = 0; y < h; ++y)
    for (int x = step; x < w; ++x)
      for (int c = 0; c < 3; ++c) reference.rgb[(size_t(y) * w + x) * 3 + c] = 1.0f;
  const Image test = constant(w, h, {0, 0, 0});
  const FlipResult r = flip_ldr(reference.view(), test.view(), with_components());
  const Errors expected = reference_flip(reference, test);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      ASSERT_NEAR(r.feature_error[i], expected.feature[i], 1e-5) << x << ", " << y;
      ASSERT_NEAR(r.colour_error[i], expected.colour[i], 2e-5) << x << ", " << y;
      ASSERT_NEAR(r.error[i], expected.error[i], 2e-5) << x << ", " << y;
    }
  // Either side of the step the edge detector covers exactly its positive (or its negative)
  // half, which sums to 1, and the point detector less: ΔE_f = (1/√2)^q_f with q_f = 1/2.
  EXPECT_NEAR(r.feature_error[step], std::pow(2.0, -0.25), 1e-6);
  EXPECT_NEAR(r.feature_error[step - 1], std::pow(2.0, -0.25), 1e-6);
  // Beyond the detectors' reach (3σ, rounded up) there is no feature at all.
  const int reach = int(std::ceil(3.0 * feature_sigma()));
  EXPECT_EQ(r.feature_error[step - 1 - reach], 0.0f);
  EXPECT_EQ(r.feature_error[step + reach], 0.0f);
  EXPECT_GT(r.feature_error[step - reach], 0.0f);
  // The error peaks at the edge: it is larger there than far out on either side.
  EXPECT_GT(r.error[step - 1], r.error[2]);
  EXPECT_GT(r.error[step], r.error[w - 3]);
}

TEST(Flip, IsolatedPointMatchesThePapersFilters) {
  const int size = 41, centre = 20;
  Image reference = constant(size, size, {0, 0, 0});
  for (int c = 0; c < 3; ++c) reference.rgb[(size_t(centre) * size + centre) * 3 + c] = 1.0f;
  const Image test = constant(size, size, {0, 0, 0});
  const FlipResult r = flip_ldr(reference.view(), test.view(), with_components());
  const Errors expected = reference_flip(reference, test);
  for (size_t i = 0; i < r.error.size(); ++i) {
    ASSERT_NEAR(r.feature_error[i], expected.feature[i], 1e-5) << i % size << ", " << i / size;
    ASSERT_NEAR(r.error[i], expected.error[i], 2e-5) << i % size << ", " << i / size;
  }
  auto feature = [&](int dx, int dy) { return r.feature_error[size_t(centre + dy) * size + centre + dx]; };
  // On the point the edge detectors see nothing (their centre weight is 0) and each point
  // detector its centre weight, −1/N with N the sum of its negative weights before scaling:
  // the magnitude is √2/N, so ΔE_f = (1/N)^q_f.
  const double s = feature_sigma();
  const int reach = int(std::ceil(3.0 * s));
  double negative = 0.0;
  for (int j = -reach; j <= reach; ++j)
    for (int i = -reach; i <= reach; ++i)
      negative += std::min(0.0, (i * i / (s * s) - 1.0) * std::exp(-(i * i + j * j) / (2.0 * s * s)));
  EXPECT_NEAR(feature(0, 0), std::sqrt(1.0 / -negative), 1e-6);
  // The response is symmetric about the point: mirrored and transposed.
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      ASSERT_NEAR(feature(dx, dy), feature(-dx, dy), 1e-6) << dx << ", " << dy;
      ASSERT_NEAR(feature(dx, dy), feature(dx, -dy), 1e-6) << dx << ", " << dy;
      ASSERT_NEAR(feature(dx, dy), feature(dy, dx), 1e-6) << dx << ", " << dy;
    }
  // Out of the CSFs' and the detectors' reach black is compared with black.
  EXPECT_EQ(r.error[0], 0.0f);
  EXPECT_EQ(feature(reach + 1, 0), 0.0f);
}

TEST(Flip, NonFiniteInputIsRefused) {
  Image good = constant(6, 4, {0.5, 0.5, 0.5});
  Image bad = good;
  bad.rgb[(1 * 6 + 3) * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
  try {
    flip_ldr(bad.view(), good.view());
    FAIL() << "a NaN was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reference image is not finite at pixel (3, 1)"), std::string::npos)
        << e.what();
  }
  bad.rgb[(1 * 6 + 3) * 3 + 1] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(flip_ldr(good.view(), bad.view()), std::invalid_argument);
  EXPECT_THROW(flip_hdr(good.view(), bad.view()), std::invalid_argument);
  EXPECT_THROW(flip_exposure_range(bad.view()), std::invalid_argument);
  const Image smaller = constant(5, 4, {0.5, 0.5, 0.5});
  EXPECT_THROW(flip_ldr(good.view(), smaller.view()), std::invalid_argument);
}

// The ACES fit of the paper, with its 0.6 pre-exposure folded in.
double aces(double x) {
  const double v = (0.6 * 0.6 * 2.51 * x * x + 0.6 * 0.03 * x) / (0.6 * 0.6 * 2.43 * x * x + 0.6 * 0.59 * x + 0.14);
  return std::clamp(v, 0.0, 1.0);
}

// Where the curve reaches 0.85, by bisection (it rises monotonically).
double aces_at_085() {
  double lo = 0.0, hi = 100.0;
  for (int i = 0; i < 200; ++i) (aces(0.5 * (lo + hi)) < 0.85 ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

Image greys(const std::vector<double>& levels) {
  Image im{int(levels.size()), 1, {}};
  for (double g : levels)
    for (int c = 0; c < 3; ++c) im.rgb.push_back(float(g));
  return im;
}

TEST(Flip, ExposureRangeFollowsThePaper) {
  // Grey's luminance is its level (the coefficients sum to 1); max 8, median 2.
  FlipExposures e = flip_exposure_range(greys({4, 0.5, 8, 2, 1}).view());
  EXPECT_NEAR(e.start, std::log2(aces_at_085() / 8.0), 1e-6);
  EXPECT_NEAR(e.stop, std::log2(aces_at_085() / 2.0), 1e-6);
  EXPECT_EQ(e.count, 2u);  // ceil(2 stops), two at least
  e = flip_exposure_range(greys({0.01, 0.02, 0.04, 64, 0.03, 0.05}).view());
  EXPECT_NEAR(e.stop, std::log2(aces_at_085() / 0.035), 1e-6);  // mean of the middle two
  EXPECT_EQ(e.count, uint32_t(std::ceil(std::log2(64 / 0.035))));
  // A black median: the median of the lit pixels, (1 + 4) / 2.
  e = flip_exposure_range(greys({0, 0, 4, 0, 1}).view());
  EXPECT_NEAR(e.stop, std::log2(aces_at_085() / 2.5), 1e-6);
  e = flip_exposure_range(greys({0, 0}).view());
  EXPECT_EQ(e.start, 0.0);
  EXPECT_EQ(e.stop, 0.0);
  EXPECT_EQ(e.count, 1u);
}

TEST(Flip, HdrConstantImagesTakeTheWorstExposure) {
  const Rgb a = {2.0, 1.0, 0.5}, b = {2.4, 0.9, 0.5};
  const FlipExposures exposures{-3.0, 2.0, 6};
  double expected = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double scale = std::exp2(-3.0 + i);
    expected = std::max(expected, colour_error({aces(scale * a[0]), aces(scale * a[1]), aces(scale * a[2])},
                                               {aces(scale * b[0]), aces(scale * b[1]), aces(scale * b[2])}));
  }
  const FlipResult r = flip_hdr(constant(24, 16, a).view(), constant(24, 16, b).view(), {}, exposures);
  for (float e : r.error) ASSERT_NEAR(e, expected, 2e-5);
  // A flat reference has one luminance, so the paper's range is the single exposure at which it
  // reaches 0.85.
  const FlipExposures own = flip_exposure_range(constant(4, 4, a).view());
  EXPECT_EQ(own.count, 1u);
}

// The error map's colours: magma's ends and middle, brighter as the error grows, and the map of
// a FLIP result pixel for pixel.
TEST(FlipMap, MagmaRunsFromBlackToLightYellowAndBrightens) {
  EXPECT_EQ(magma(0.0f), (std::array<uint8_t, 3>{0, 0, 4}));
  EXPECT_EQ(magma(0.5f), (std::array<uint8_t, 3>{183, 55, 121}));
  EXPECT_EQ(magma(1.0f), (std::array<uint8_t, 3>{252, 253, 191}));
  EXPECT_EQ(magma(2.0f), magma(1.0f)) << "clamped";
  EXPECT_EQ(magma(-1.0f), magma(0.0f)) << "clamped";
  double last = -1.0;
  for (int i = 0; i <= 100; ++i) {
    const std::array<uint8_t, 3> c = magma(i / 100.0f);
    const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    EXPECT_GE(luma, last) << "at " << i / 100.0;
    last = luma;
  }
  FlipResult flip;
  flip.width = 2;
  flip.height = 1;
  flip.error = {0.0f, 1.0f};
  EXPECT_EQ(flip_map_rgba8(flip), (std::vector<uint8_t>{0, 0, 4, 255, 252, 253, 191, 255}));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
