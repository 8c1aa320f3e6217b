// CPU references for the sky's LUTs (passes/sky/), shared by their unit test and the benchmark.
// Written in double precision from the atmosphere's definition (passes/sky/atmosphere.glsl.h)
// and Hillaire's (2020) model, not from the shaders: the transmittance by adaptive Simpson
// quadrature of each constituent's optical depth, the sky's radiance by a midpoint ray march
// whose transmittance toward the light is its own sum, not the LUT.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <limits>
#include <vector>

#include "passes/core/format.h"
#include "passes/sky/atmosphere.glsl.h"

namespace nightcap::reference {

using glm::dvec3;

struct Model {
  double ground, top, ozone_centre, ozone_half_width, rayleigh_height, mie_height, g;
  dvec3 rayleigh, mie, mie_extinction, ozone;

  explicit Model(const GpuAtmosphere& a)
      : ground(a.radii.x),
        top(a.radii.y),
        ozone_centre(a.ozone.w),
        ozone_half_width(a.radii.z),
        rayleigh_height(a.rayleigh.w),
        mie_height(a.mie_scattering.w),
        g(a.mie_extinction.w),
        rayleigh(a.rayleigh),
        mie(a.mie_scattering),
        mie_extinction(a.mie_extinction),
        ozone(a.ozone) {}

  double rayleigh_density(double h) const { return std::exp(-std::max(h, 0.0) / rayleigh_height); }
  double mie_density(double h) const { return std::exp(-std::max(h, 0.0) / mie_height); }
  double ozone_density(double h) const {
    return std::max(0.0, 1.0 - std::abs(std::max(h, 0.0) - ozone_centre) / ozone_half_width);
  }
  dvec3 extinction(double h) const {
    return rayleigh * rayleigh_density(h) + mie_extinction * mie_density(h) + ozone * ozone_density(h);
  }
  // Height above the ground after t km along a ray from radius r with zenith cosine mu.
  double height(double r, double mu, double t) const { return std::sqrt(t * t + 2 * r * mu * t + r * r) - ground; }
  double distance_out(double r, double mu) const {
    return std::max(0.0, -r * mu + std::sqrt(std::max(r * r * (mu * mu - 1) + top * top, 0.0)));
  }
  bool meets_ground(double r, double mu) const { return mu < 0 && r * r * (mu * mu - 1) + ground * ground >= 0; }
};

inline double simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb,
                      double whole, double tolerance, int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
  if (depth <= 0 || std::abs(left + right - whole) <= 15 * tolerance) return left + right + (left + right - whole) / 15;
  return simpson(f, a, m, fa, flm, fm, left, tolerance / 2, depth - 1) +
         simpson(f, m, b, fm, frm, fb, right, tolerance / 2, depth - 1);
}

// ∫ f over [a, b] to `tolerance`, started from 16 panels so that no feature hides between samples.
inline double integrate(const std::function<double(double)>& f, double a, double b, double tolerance) {
  double sum = 0;
  const int panels = 16;
  for (int k = 0; k < panels; ++k) {
    const double x0 = a + (b - a) * k / panels, x1 = a + (b - a) * (k + 1) / panels, xm = 0.5 * (x0 + x1);
    const double f0 = f(x0), fm = f(xm), f1 = f(x1);
    sum += simpson(f, x0, x1, f0, fm, f1, (x1 - x0) / 6 * (f0 + 4 * fm + f1), tolerance / panels, 30);
  }
  return sum;
}

inline dvec3 transmittance_reference(const Model& m, double r, double mu) {
  const double d = m.distance_out(r, mu);
  const auto along = [&](double (Model::*density)(double) const) {
    return integrate([&](double t) { return (m.*density)(m.height(r, mu, t)); }, 0.0, d, 1e-9);
  };
  const double rayleigh = along(&Model::rayleigh_density), mie = along(&Model::mie_density),
               ozone = along(&Model::ozone_density);
  return glm::exp(-(m.rayleigh * rayleigh + m.mie_extinction * mie + m.ozone * ozone));
}

// A midpoint sum of `samples` steps: the reference's own transmittance toward the light.
inline dvec3 transmittance_sum(const Model& m, double r, double mu, int samples) {
  if (m.meets_ground(r, mu)) return dvec3(0.0);
  const double step = m.distance_out(r, mu) / samples;
  dvec3 depth(0.0);
  for (int i = 0; i < samples; ++i) depth += m.extinction(m.height(r, mu, (i + 0.5) * step));
  return glm::exp(-depth * step);
}

inline double texel_coordinate(double x, double n) { return 0.5 / n + x * (1.0 - 1.0 / n); }
inline double unit_of_texel_coordinate(double u, double n) { return (u - 0.5 / n) / (1.0 - 1.0 / n); }

// The transmittance LUT's parameterisation (Bruneton 2017), in double.
inline void transmittance_r_mu(const Model& m, double u, double v, double w, double h, double& r, double& mu) {
  const double x_mu = unit_of_texel_coordinate(u, w), x_r = unit_of_texel_coordinate(v, h);
  const double horizon = std::sqrt(m.top * m.top - m.ground * m.ground);
  const double rho = horizon * x_r;
  r = std::sqrt(rho * rho + m.ground * m.ground);
  const double d_min = m.top - r, d_max = rho + horizon, d = d_min + x_mu * (d_max - d_min);
  mu = d == 0 ? 1.0 : std::clamp((horizon * horizon - rho * rho - d * d) / (2 * r * d), -1.0, 1.0);
}

// Its inverse: where a W×H transmittance LUT holds radius r and zenith cosine mu.
inline glm::dvec2 transmittance_uv(const Model& m, double r, double mu, double w, double h) {
  const double horizon = std::sqrt(m.top * m.top - m.ground * m.ground);
  const double rho = std::sqrt(std::max(r * r - m.ground * m.ground, 0.0));
  const double d = m.distance_out(r, mu), d_min = m.top - r, d_max = rho + horizon;
  return {texel_coordinate((d - d_min) / (d_max - d_min), w), texel_coordinate(rho / horizon, h)};
}

inline dvec3 texel_of(const std::vector<uint8_t>& bytes, uint32_t width, uint32_t x, uint32_t y) {
  float t[4];
  decode_texel(*format_info(VK_FORMAT_R16G16B16A16_SFLOAT), 0, bytes, uint64_t(y) * width + x, t);
  return dvec3(t[0], t[1], t[2]);
}

// Bilinear lookup with clamp-to-edge, as the sampler reads a W×H RGBA16F LUT at uv.
inline dvec3 bilinear(const std::vector<uint8_t>& lut, uint32_t w, uint32_t h, double u, double v) {
  const double x = u * w - 0.5, y = v * h - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
  const auto at = [&](double xi, double yi) {
    return texel_of(lut, w, uint32_t(std::clamp(xi, 0.0, w - 1.0)), uint32_t(std::clamp(yi, 0.0, h - 1.0)));
  };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

// Trilinear lookup with clamp-to-edge, as the sampler reads a W×H×D RGBA16F volume at uvw: rgba.
inline glm::dvec4 trilinear(const std::vector<uint8_t>& volume, uint32_t w, uint32_t h, uint32_t d, double u, double v,
                            double s) {
  const double x = u * w - 0.5, y = v * h - 0.5, z = s * d - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), z0 = std::floor(z);
  const auto at = [&](double xi, double yi, double zi) {
    const uint64_t index = (uint64_t(std::clamp(zi, 0.0, d - 1.0)) * h + uint64_t(std::clamp(yi, 0.0, h - 1.0))) * w +
                           uint64_t(std::clamp(xi, 0.0, w - 1.0));
    float t[4];
    decode_texel(*format_info(VK_FORMAT_R16G16B16A16_SFLOAT), 0, volume, index, t);
    return glm::dvec4(t[0], t[1], t[2], t[3]);
  };
  const auto plane = [&](double zi) {
    return glm::mix(glm::mix(at(x0, y0, zi), at(x0 + 1, y0, zi), x - x0),
                    glm::mix(at(x0, y0 + 1, zi), at(x0 + 1, y0 + 1, zi), x - x0), y - y0);
  };
  return glm::mix(plane(z0), plane(z0 + 1), z - z0);
}

struct Air {
  dvec3 in_scattered;
  double transmittance;
};

// What sky.aerial_perspective (a W×H×N volume) says of the air along the view ray through screen
// point uv to `distance_km`, read as lighting.composite reads it: slice k ends at
// kSkyAerialDistanceKm ((k + 1) / N)² (nearer than the first slice's end, the first slice), and
// holds the in-scattered radiance and the optical depth per km of that length.
inline Air aerial_perspective(const std::vector<uint8_t>& volume, uint32_t w, uint32_t h, uint32_t n,
                              const glm::dvec2& uv, double distance_km) {
  const double slice = n * std::sqrt(distance_km / kSkyAerialDistanceKm) - 1.0;
  const glm::dvec4 air = trilinear(volume, w, h, n, uv.x, uv.y, (std::max(slice, 0.0) + 0.5) / n);
  return {dvec3(air) * distance_km, std::exp(-air.w * distance_km)};
}

// The view direction of sky.view's texel (x, y) of a W×H LUT seen from radius r, in the LUT's
// frame (y up, the light in the xy plane toward +x): its parameterisation in double.
inline dvec3 sky_view_direction(const Model& m, uint32_t x, uint32_t y, uint32_t w, uint32_t h, double r) {
  const double u = unit_of_texel_coordinate((x + 0.5) / w, w), v = unit_of_texel_coordinate((y + 0.5) / h, h);
  const double from_nadir = std::acos(std::sqrt(r * r - m.ground * m.ground) / r);
  const double zenith_to_horizon = glm::pi<double>() - from_nadir;
  double zenith;
  if (v < 0.5) {
    const double s = 1 - 2 * v;
    zenith = zenith_to_horizon * (1 - s * s);
  } else {
    const double s = 2 * v - 1;
    zenith = zenith_to_horizon + from_nadir * s * s;
  }
  const double cos_azimuth = 1 - 2 * u * u, cz = std::cos(zenith), sz = std::sin(zenith);
  return dvec3(sz * cos_azimuth, cz, sz * std::sqrt(std::max(0.0, 1 - cos_azimuth * cos_azimuth)));
}

// Where sky.view's parameterisation puts a unit direction (the LUT's frame, as above) seen from
// radius r, as uv in [0, 1]² of a W×H LUT: sky_view_direction inverted.
inline glm::dvec2 sky_view_uv(const Model& m, const dvec3& d, double r, uint32_t w, uint32_t h) {
  const double from_nadir = std::acos(std::sqrt(r * r - m.ground * m.ground) / r);
  const double zenith_to_horizon = glm::pi<double>() - from_nadir;
  const double zenith = std::acos(std::clamp(d.y, -1.0, 1.0));
  const double v = zenith <= zenith_to_horizon
                       ? 0.5 * (1 - std::sqrt(std::max(1 - zenith / zenith_to_horizon, 0.0)))
                       : 0.5 + 0.5 * std::sqrt(std::min((zenith - zenith_to_horizon) / from_nadir, 1.0));
  const double flat = std::hypot(d.x, d.z), cos_azimuth = flat > 1e-12 ? d.x / flat : 1.0;
  const double u = std::sqrt(std::clamp(0.5 - 0.5 * cos_azimuth, 0.0, 1.0));
  return {texel_coordinate(u, w), texel_coordinate(v, h)};
}

// From radius r along zenith cosine mu, the distance to the ground; infinity for a ray that misses it.
inline double ground_distance(const Model& m, double r, double mu) {
  return m.meets_ground(r, mu) ? -r * mu - std::sqrt(std::max(r * r * (mu * mu - 1) + m.ground * m.ground, 0.0))
                               : std::numeric_limits<double>::infinity();
}

// The transmittance to the atmosphere's top in double: transmittance_reference (adaptive
// quadrature) at the texels of a W×H table in Bruneton's parameterisation, read bilinearly.
class TransmittanceTable {
 public:
  TransmittanceTable(const Model& m, uint32_t width, uint32_t height) : m_(m), width_(width), height_(height) {
    texels_.resize(size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        double r, mu;
        transmittance_r_mu(m, (x + 0.5) / width, (y + 0.5) / height, width, height, r, mu);
        texels_[size_t(y) * width + x] = transmittance_reference(m, r, mu);
      }
  }
  // From radius r along zenith cosine mu; 0 where the ray meets the ground.
  dvec3 operator()(double r, double mu) const {
    if (m_.meets_ground(r, mu)) return dvec3(0.0);
    const glm::dvec2 uv = transmittance_uv(m_, r, mu, width_, height_);
    const double x = uv.x * width_ - 0.5, y = uv.y * height_ - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const auto at = [&](double xi, double yi) {
      return texels_[size_t(std::clamp(yi, 0.0, height_ - 1.0)) * width_ + size_t(std::clamp(xi, 0.0, width_ - 1.0))];
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), x - x0), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), x - x0),
                    y - y0);
  }

 private:
  const Model& m_;
  uint32_t width_, height_;
  std::vector<dvec3> texels_;
};

// Hillaire's (2020) multiple-scattering factor Ψ = L₂ / (1 − f) at height h (km) for a light of
// unit illuminance whose zenith cosine there is mu_light: L₂ the light scattered twice toward the
// point (the medium's single scattering of the light, and the ground's Lambertian bounce of it,
// gathered over the sphere with the isotropic phase), f the share the medium around scatters back
// (∫ over the sphere of the scattering along each ray, times the isotropic phase). The sphere by
// a `directions` × `directions` midpoint grid in cos θ and φ, each ray by `steps` midpoint steps
// to the ground or the top, each step's transmittance toward the light from `toward_light`.
inline dvec3 multiple_scattering_reference(const Model& m, const TransmittanceTable& toward_light, double h,
                                           double mu_light, double ground_albedo, int directions, int steps) {
  const double pi = glm::pi<double>(), isotropic = 1.0 / (4.0 * pi), r = m.ground + h;
  const dvec3 light(std::sqrt(std::max(1.0 - mu_light * mu_light, 0.0)), mu_light, 0.0);
  dvec3 second(0.0), back(0.0);
  for (int a = 0; a < directions; ++a)
    for (int b = 0; b < directions; ++b) {
      const double cos_theta = 1.0 - 2.0 * (b + 0.5) / directions, phi = 2.0 * pi * (a + 0.5) / directions;
      const double sin_theta = std::sqrt(std::max(1.0 - cos_theta * cos_theta, 0.0));
      const dvec3 direction(sin_theta * std::cos(phi), cos_theta, sin_theta * std::sin(phi));
      const bool ground = m.meets_ground(r, cos_theta);
      const double length = ground ? ground_distance(m, r, cos_theta) : m.distance_out(r, cos_theta);
      const double dt = length / steps;
      dvec3 throughput(1.0);
      for (int i = 0; i < steps; ++i) {
        const dvec3 p = dvec3(0, r, 0) + direction * ((i + 0.5) * dt);
        const double r_p = glm::length(p), h_p = r_p - m.ground;
        const dvec3 scattering = m.rayleigh * m.rayleigh_density(h_p) + m.mie * m.mie_density(h_p);
        const dvec3 half_step = glm::exp(-m.extinction(h_p) * (0.5 * dt));
        const dvec3 weight = throughput * half_step * dt;
        second += weight * scattering * toward_light(r_p, glm::dot(p, light) / r_p) * isotropic;
        back += weight * scattering;
        throughput *= half_step * half_step;
      }
      if (ground) {
        const dvec3 p = dvec3(0, r, 0) + direction * length;
        const double mu_ground = glm::dot(p, light) / glm::length(p);
        second += throughput * toward_light(m.ground, mu_ground) * std::max(mu_ground, 0.0) * ground_albedo / pi;
      }
    }
  const double count = double(directions) * directions;
  return (second / count) / (1.0 - glm::min(back / count, dvec3(0.99)));
}

// The light the air scatters toward a ray's start from a light of unit radiance toward `light`,
// and the transmittance along the ray, marched by midpoint steps from radius r along `direction`
// (unit vectors in a frame whose y is the zenith at the start): single scattering with Rayleigh's
// and Cornette-Shanks's phase functions and a `light_samples`-sample transmittance toward the
// light, plus the multiple scattering LUT `ms` (W×H RGBA16F, as sky.multiscattering writes it)
// sampled bilinearly.
class AirMarch {
 public:
  AirMarch(const Model& m, const std::vector<uint8_t>& ms, uint32_t ms_width, uint32_t ms_height, double r,
           const dvec3& direction, const dvec3& light, int light_samples)
      : m_(m),
        ms_(ms),
        ms_width_(ms_width),
        ms_height_(ms_height),
        r_(r),
        direction_(direction),
        light_(light),
        light_samples_(light_samples) {
    const double c = glm::dot(direction, light), pi = glm::pi<double>(), g = m.g;
    rayleigh_phase_ = 3.0 / (16 * pi) * (1 + c * c);
    mie_phase_ = 3.0 / (8 * pi) * (1 - g * g) / (2 + g * g) * (1 + c * c) / std::pow(1 + g * g - 2 * g * c, 1.5);
  }

  // Adds the step from t0 to t1 km along the ray, sampled at its middle.
  void step(double t0, double t1) {
    const double dt = t1 - t0;
    const dvec3 p = dvec3(0, r_, 0) + direction_ * (0.5 * (t0 + t1));
    const double r_p = glm::length(p), h = r_p - m_.ground, mu_p = glm::dot(p, light_) / r_p;
    const dvec3 sun = transmittance_sum(m_, r_p, mu_p, light_samples_);
    const dvec3 multiple =
        bilinear(ms_, ms_width_, ms_height_, texel_coordinate(std::clamp(mu_p * 0.5 + 0.5, 0.0, 1.0), ms_width_),
                 texel_coordinate(std::clamp(h / (m_.top - m_.ground), 0.0, 1.0), ms_height_));
    const dvec3 source = m_.rayleigh * m_.rayleigh_density(h) * (sun * rayleigh_phase_ + multiple) +
                         m_.mie * m_.mie_density(h) * (sun * mie_phase_ + multiple);
    // The midpoint rule: the throughput to the step's middle.
    const dvec3 half_step = glm::exp(-m_.extinction(h) * (0.5 * dt));
    radiance += transmittance * half_step * source * dt;
    transmittance *= half_step * half_step;
  }

  dvec3 radiance{0.0}, transmittance{1.0};

 private:
  const Model& m_;
  const std::vector<uint8_t>& ms_;
  uint32_t ms_width_, ms_height_;
  double r_;
  dvec3 direction_, light_;
  int light_samples_;
  double rayleigh_phase_ = 0, mie_phase_ = 0;
};

// The sky's radiance along `direction` from radius r (AirMarch's), marched in `steps` equal
// steps to the ground or the top, `steps` samples toward the light.
inline dvec3 sky_radiance(const Model& m, const std::vector<uint8_t>& ms, uint32_t ms_width, uint32_t ms_height,
                          double r, const dvec3& direction, const dvec3& light, int steps) {
  const double length = std::min(ground_distance(m, r, direction.y), m.distance_out(r, direction.y));
  AirMarch march(m, ms, ms_width, ms_height, r, direction, light, steps);
  for (int i = 0; i < steps; ++i) march.step(length * i / steps, length * (i + 1) / steps);
  return march.radiance;
}

}  // namespace nightcap::reference
