// A CPU double-precision reference for lighting.deferred, shared by its test and the benchmark.
// It is written from the lighting model the pass documents, not from its shader: Lambert
// diffuse; GGX specular with height-correlated Smith visibility and Schlick Fresnel
// (f0 = mix(0.04, albedo, metallic)); glTF's range window (1 − (d/range)⁴)²; spot falloff t²
// with t the position of cos θ between the outer and inner cone; tube lights as line lights of
// candela per metre, integrated along the segment adaptively to ~1e-11 relative. Inputs are the
// decoded G-buffer codes and the recorded float constants, read as doubles.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "passes/frame/gpu_types.h"

namespace nightcap::reference {

using glm::dvec3;

// A2B10G10R10 UNORM: the three 10-bit codes as the sampler returns them.
inline dvec3 decode_unorm10x3(uint32_t word) {
  return dvec3(word & 1023u, (word >> 10) & 1023u, (word >> 20) & 1023u) / 1023.0;
}

// gbuffer.normal stores 0.5n + 0.5.
inline dvec3 decode_normal(uint32_t word) { return glm::normalize(decode_unorm10x3(word) * 2.0 - 1.0); }

// The camera-relative position the pixel centre and its device depth stand for, through the
// recorded inverse view-projection.
inline dvec3 reconstruct_position(const GpuView& frame, uint32_t x, uint32_t y, float depth) {
  const double ndc_x = (x + 0.5) * double(frame.viewport.z) * 2.0 - 1.0;
  const double ndc_y = (y + 0.5) * double(frame.viewport.w) * 2.0 - 1.0;
  const glm::dvec4 p = glm::dmat4(frame.inverse_view_projection) * glm::dvec4(ndc_x, ndc_y, depth, 1.0);
  return dvec3(p) / p.w;
}

struct Surface {
  dvec3 position;  // camera-relative
  dvec3 n, v;
  dvec3 albedo;
  double metallic = 0, alpha = 0;
};

// From the decoded G-buffer: albedo and normal words, material bytes (r metallic, g roughness).
inline Surface make_surface(const dvec3& position, uint32_t normal_word, uint32_t albedo_word, const uint8_t* material,
                            double min_roughness) {
  Surface s;
  s.position = position;
  s.n = decode_normal(normal_word);
  s.v = -glm::normalize(position);
  s.albedo = decode_unorm10x3(albedo_word);
  s.metallic = material[0] / 255.0;
  const double roughness = std::max(material[1] / 255.0, min_roughness);
  s.alpha = roughness * roughness;
  return s;
}

struct Shade {
  dvec3 diffuse{0.0}, specular{0.0};
};

inline double range_window(double distance, double range) {
  if (range <= 0) return 1;
  const double r = distance / range;
  const double w = std::clamp(1 - r * r * r * r, 0.0, 1.0);
  return w * w;
}

inline dvec3 lambert_cos(const Surface& s, const dvec3& l) {
  return s.albedo * (1 - s.metallic) * (std::max(glm::dot(s.n, l), 0.0) / std::numbers::pi);
}

// GGX BRDF × n·l toward v for light arriving along unit l, as the two parts Schlick's Fresnel
// weighs: D·V·n·l and D·V·n·l·(1 − v·h)⁵; the BRDF is f0·x + (1 − f0)·y.
inline glm::dvec2 ggx_cos_parts(const Surface& s, const dvec3& l) {
  const double n_l = glm::dot(s.n, l), n_v = glm::dot(s.n, s.v);
  if (n_l <= 0 || n_v <= 0) return glm::dvec2(0.0);
  const dvec3 h = glm::normalize(l + s.v);
  const dvec3 nxh = glm::cross(s.n, h);
  const double n_h = glm::dot(s.n, h), a2 = s.alpha * s.alpha;
  // (n·h)²(α²−1)+1 written as sin²θh + α²cos²θh, so the peak does not depend on 1 − (n·h)².
  const double k = glm::dot(nxh, nxh) + n_h * n_h * a2;
  const double d = a2 / (std::numbers::pi * k * k);
  const double vis = 0.5 / (n_l * std::sqrt(n_v * n_v * (1 - a2) + a2) + n_v * std::sqrt(n_l * n_l * (1 - a2) + a2));
  const double base = d * vis * n_l;
  return {base, base * std::pow(1 - glm::dot(s.v, h), 5.0)};
}

inline dvec3 fresnel_f0(const Surface& s) { return glm::mix(dvec3(0.04), s.albedo, s.metallic); }

inline dvec3 ggx_cos(const Surface& s, const dvec3& l) {
  const glm::dvec2 parts = ggx_cos_parts(s, l);
  const dvec3 f0 = fresnel_f0(s);
  return f0 * parts.x + (1.0 - f0) * parts.y;
}

// Sun or directional light: `direction` is the way light travels, `irradiance` at normal
// incidence.
inline Shade shade_directional(const Surface& s, const dvec3& direction, const dvec3& irradiance) {
  const dvec3 l = -glm::normalize(direction);
  return {lambert_cos(s, l) * irradiance, ggx_cos(s, l) * irradiance};
}

// Point or spot light (GpuLight layout), intensities multiplied by `intensity_scale`.
inline Shade shade_punctual(const Surface& s, const GpuLight& light, double intensity_scale) {
  const dvec3 to_light = dvec3(glm::vec3(light.position_type)) - s.position;
  const double d = glm::length(to_light);
  const double range = light.color_range.w;
  if (d == 0 || (range > 0 && d >= range)) return {};
  const dvec3 l = to_light / d;
  double attenuation = range_window(d, range) / (d * d);
  if (uint32_t(light.position_type.w) == 2) {
    const double cos_outer = light.direction_cos_outer.w, cos_inner = light.cos_inner.x;
    const double t = std::clamp(
        (glm::dot(dvec3(glm::vec3(light.direction_cos_outer)), -l) - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
    attenuation *= t * t;
  }
  const dvec3 e = dvec3(glm::vec3(light.color_range)) * intensity_scale * attenuation;
  return {lambert_cos(s, l) * e, ggx_cos(s, l) * e};
}

// How far `shade` (a reference over the surface) moves when the position moves by 4 float ulps
// (2⁻²¹·|p|) or a normal component by 2⁻²¹, summed over the six directions: a pass reconstructs
// the position and decodes the normal in float, so no float implementation pins its result
// closer. It matters at the terminator and at grazing angles, for lights much nearer the
// surface than the camera, and at the peak of the narrowest highlights (D changes by up to 2/α
// per radian of the half vector).
template <typename ShadeOf>
Shade input_spread(const Surface& s, ShadeOf&& shade) {
  Shade total;
  for (int axis = 0; axis < 6; ++axis) {
    Surface plus = s, minus = s;
    if (axis < 3) {
      const double step = std::ldexp(glm::length(s.position), -21);
      plus.position[axis] += step;
      minus.position[axis] -= step;
      plus.v = -glm::normalize(plus.position);
      minus.v = -glm::normalize(minus.position);
    } else {
      plus.n[axis - 3] += std::ldexp(1.0, -21);
      minus.n[axis - 3] -= std::ldexp(1.0, -21);
      plus.n = glm::normalize(plus.n);
      minus.n = glm::normalize(minus.n);
    }
    const Shade a = shade(plus), b = shade(minus);
    total.diffuse += glm::abs(a.diffuse - b.diffuse) * 0.5;
    total.specular += glm::abs(a.specular - b.specular) * 0.5;
  }
  return total;
}

// ∫ f over [a, b] by adaptive Simpson, each panel refined until its two halves agree to
// `tolerance` (absolute, halved with each split).
template <class F>
double adaptive_simpson(const F& f, double a, double b, double tolerance) {
  struct Panel {
    double a, b, fa, fm, fb, whole, tolerance;
    int depth;
  };
  const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
  std::vector<Panel> stack{{a, b, fa, fm, fb, (b - a) / 6 * (fa + 4 * fm + fb), tolerance, 0}};
  double sum = 0;
  while (!stack.empty()) {
    const Panel p = stack.back();
    stack.pop_back();
    const double m = 0.5 * (p.a + p.b);
    const double flm = f(0.5 * (p.a + m)), frm = f(0.5 * (m + p.b));
    const double left = (m - p.a) / 6 * (p.fa + 4 * flm + p.fm);
    const double right = (p.b - m) / 6 * (p.fm + 4 * frm + p.fb);
    if (p.depth >= 50 || std::abs(left + right - p.whole) <= 15 * p.tolerance) {
      sum += left + right + (left + right - p.whole) / 15;
      continue;
    }
    stack.push_back({p.a, m, p.fa, flm, p.fm, left, 0.5 * p.tolerance, p.depth + 1});
    stack.push_back({m, p.b, p.fm, frm, p.fb, right, 0.5 * p.tolerance, p.depth + 1});
  }
  return sum;
}

// ∫₀¹ f over pieces split at `breaks` (kinks and peaks of the integrand), to ~`relative` of
// the whole integral (absolute: 1e-20 at least), estimated first by a 64-panel Simpson sum per piece.
template <class F>
double integrate_unit(const F& f, std::vector<double> breaks, double relative) {
  breaks.push_back(0);
  breaks.push_back(1);
  std::erase_if(breaks, [](double t) { return !(t >= 0 && t <= 1); });
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  double estimate = 0;
  for (size_t i = 0; i + 1 < breaks.size(); ++i) {
    const int panels = 64;
    const double h = (breaks[i + 1] - breaks[i]) / panels;
    for (int k = 0; k < panels; ++k) {
      const double a = breaks[i] + k * h;
      estimate += h / 6 * (f(a) + 4 * f(a + h / 2) + f(a + h));
    }
  }
  if (estimate == 0) return 0;
  // Never below 1e-20 absolute: integrals that small (a tube all but out of range) are noise of
  // the range window near its edge, and no subdivision would settle them.
  const double tolerance = std::max(relative * std::abs(estimate), 1e-20);
  double sum = 0;
  for (size_t i = 0; i + 1 < breaks.size(); ++i)
    sum += adaptive_simpson(f, breaks[i], breaks[i + 1], tolerance * (breaks[i + 1] - breaks[i]));
  return sum;
}

// A tube light as a line of candela per metre from position_type.xyz to end_radius.xyz. Its
// diffuse and specular, each integrated over the segment.
class Tube {
 public:
  Tube(const Surface& s, const GpuLight& light, double intensity_scale)
      : s_(s),
        a_(dvec3(glm::vec3(light.position_type)) - s.position),
        ab_(dvec3(glm::vec3(light.end_radius)) - dvec3(glm::vec3(light.position_type))),
        range_(light.color_range.w),
        intensity_(dvec3(glm::vec3(light.color_range)) * intensity_scale) {}

  dvec3 diffuse() const {
    const double len = glm::length(ab_);
    if (len == 0) return dvec3(0.0);
    const double irradiance = integrate_unit([&](double t) { return cosine_over_d2(t); }, kinks(), 1e-11);
    return s_.albedo * (1 - s_.metallic) / std::numbers::pi * intensity_ * (irradiance * len);
  }

  dvec3 specular() const {
    const double len = glm::length(ab_);
    if (len == 0) return dvec3(0.0);
    std::vector<double> breaks = kinks();
    breaks.push_back(specular_peak());
    auto part = [&](int i) {
      return integrate_unit(
          [&](double t) {
            const dvec3 q = a_ + ab_ * t;
            const double d = glm::length(q);
            return d == 0 ? 0.0 : ggx_cos_parts(s_, q / d)[i] * range_window(d, range_) / (d * d);
          },
          breaks, 1e-9);
    };
    const dvec3 f0 = fresnel_f0(s_);
    return (f0 * part(0) + (1.0 - f0) * part(1)) * intensity_ * len;
  }

 private:
  // n·l / d² × window at parameter t.
  double cosine_over_d2(double t) const {
    const dvec3 q = a_ + ab_ * t;
    const double d = glm::length(q);
    return d == 0 ? 0.0 : std::max(glm::dot(s_.n, q), 0.0) / (d * d * d) * range_window(d, range_);
  }

  // Where n·l changes sign, where the distance crosses the range, and the nearest point.
  std::vector<double> kinks() const {
    std::vector<double> t;
    const double n_ab = glm::dot(s_.n, ab_);
    if (n_ab != 0) t.push_back(-glm::dot(s_.n, a_) / n_ab);
    const double aa = glm::dot(ab_, ab_), b = glm::dot(a_, ab_);
    t.push_back(-b / aa);
    if (range_ > 0) {
      const double c = glm::dot(a_, a_) - range_ * range_, disc = b * b - aa * c;
      if (disc >= 0) {
        t.push_back((-b - std::sqrt(disc)) / aa);
        t.push_back((-b + std::sqrt(disc)) / aa);
      }
    }
    return t;
  }

  // The parameter where the half vector comes closest to n: the centre of the GGX lobe on the
  // segment, found on a dense grid and refined by golden-section search.
  double specular_peak() const {
    auto sin2 = [&](double t) {
      const dvec3 q = a_ + ab_ * t;
      const double d = glm::length(q);
      if (d == 0) return 1.0;
      const dvec3 c = glm::cross(s_.n, glm::normalize(q / d + s_.v));
      return glm::dot(c, c);
    };
    const int grid = 2048;
    int best = 0;
    for (int i = 1; i <= grid; ++i)
      if (sin2(double(i) / grid) < sin2(double(best) / grid)) best = i;
    double lo = std::max(0, best - 1) / double(grid), hi = std::min(grid, best + 1) / double(grid);
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int i = 0; i < 100; ++i) {
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      if (sin2(x1) < sin2(x2))
        hi = x2;
      else
        lo = x1;
    }
    return 0.5 * (lo + hi);
  }

  Surface s_;
  dvec3 a_, ab_;  // surface → first end; first → second end
  double range_;
  dvec3 intensity_;
};

}  // namespace nightcap::reference
