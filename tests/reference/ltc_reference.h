// Tube and sphere lights through an LTC table (passes/lighting/ltc/ltc.h) against the integral of
// GGX along the segment (lighting_reference.h, Tube) and over the sphere's cap: the cases of
// shared/design/accuracy.md's `lighting.tiled` tube-light row, and spheres placed alike, for
// tests/unit/ltc_test.cpp and the benchmark's ltc section.
//
// A case: the shading point at the origin, n = +z, the view θv from n in the xz-plane; a tube
// of one candela per metre centred 2 m away on the mirror direction (where the lobe's peak is
// for smooth surfaces, so the relative error is that of what a highlight shows), of length
// 0.25, 1 or 4 m, lying across the plane of incidence or in it (perpendicular to the mirror
// direction: the length that dips toward the horizon at grazing views). Each case is taken for
// a dielectric (f0 = 0.04) and a metal (f0 = 1).
#pragma once

#include <vector>

#include "passes/lighting/ltc/ltc.h"
#include "passes/scene/scene.h"
#include "tests/reference/lighting_reference.h"

namespace nightcap::reference {

struct TubeCase {
  double roughness, view_degrees, length, f0;
  bool across;  // across the plane of incidence, else in it
  dvec3 v, end1, end2;
};

inline const std::vector<double>& tube_lengths() {
  static const std::vector<double> lengths{0.25, 1.0, 4.0};
  return lengths;
}

inline std::vector<TubeCase> tube_cases(const std::vector<double>& roughnesses, const std::vector<double>& views) {
  std::vector<TubeCase> cases;
  for (double roughness : roughnesses)
    for (double view : views)
      for (double length : tube_lengths())
        for (bool across : {true, false})
          for (double f0 : {0.04, 1.0}) {
            const double theta = view * std::numbers::pi / 180;
            const dvec3 v(std::sin(theta), 0, std::cos(theta)), mirror(-v.x, 0, v.z);
            const dvec3 direction = across ? dvec3(0, 1, 0) : dvec3(v.z, 0, v.x);
            const dvec3 centre = 2.0 * mirror;
            // The ends as the float GpuLight holds them, for both evaluations.
            const dvec3 end1(glm::vec3(centre - 0.5 * length * direction));
            const dvec3 end2(glm::vec3(centre + 0.5 * length * direction));
            cases.push_back({roughness, view, length, f0, across, v, end1, end2});
          }
  return cases;
}

// The specular the reference integrates along the segment.
inline double reference_specular(const TubeCase& c) {
  Surface s;
  s.position = dvec3(0.0);
  s.n = dvec3(0, 0, 1);
  s.v = c.v;
  s.alpha = c.roughness * c.roughness;
  // f0 = mix(0.04, albedo, metallic) is the albedo itself for a metal.
  s.metallic = 1;
  s.albedo = dvec3(c.f0);
  GpuLight light{};
  light.position_type = glm::vec4(glm::vec3(c.end1), float(LightType::tube));
  light.end_radius = glm::vec4(glm::vec3(c.end2), 0.0f);
  light.color_range = glm::vec4(1, 1, 1, 0);
  return Tube(s, light, 1.0).specular().x;
}

// The specular the LTC table gives.
inline double ltc_specular(const ltc::Table& table, const TubeCase& c) {
  const ltc::TubeShade shade = ltc::shade_tube(table, dvec3(0, 0, 1), c.v, c.roughness, c.end1, c.end2, 0);
  return c.f0 * shade.specular.x + (1 - c.f0) * shade.specular.y;
}

// A sphere of radius 0.05, 0.2 or 0.6 m centred 2 m away on the mirror direction, per unit
// radiance, for a dielectric and a metal.
struct SphereCase {
  double roughness, view_degrees, radius, f0;
  dvec3 v, centre;
};

inline std::vector<SphereCase> sphere_cases(const std::vector<double>& roughnesses, const std::vector<double>& views) {
  std::vector<SphereCase> cases;
  for (double roughness : roughnesses)
    for (double view : views)
      for (double radius : {0.05, 0.2, 0.6})
        for (double f0 : {0.04, 1.0}) {
          const double theta = view * std::numbers::pi / 180;
          const dvec3 v(std::sin(theta), 0, std::cos(theta));
          cases.push_back({roughness, view, radius, f0, v, 2.0 * dvec3(-v.x, 0, v.z)});
        }
  return cases;
}

// GGX's specular over the cap the sphere covers, in polar coordinates about its centre: the
// polar angle 2·atan(w·tan t) gathers the nodes within w ≈ 2α of the centre, where the lobe of
// a smooth surface is; midpoint rule in t and in the azimuth.
inline double reference_sphere_specular(const SphereCase& c, int nodes = 400) {
  Surface s;
  s.n = dvec3(0, 0, 1);
  s.v = c.v;
  s.alpha = c.roughness * c.roughness;
  const double distance = glm::length(c.centre), cap = std::asin(c.radius / distance);
  const double width = std::min(cap, 2 * s.alpha + 1e-3), top = std::atan(std::tan(cap / 2) / width);
  const dvec3 axis = c.centre / distance;
  const dvec3 e1 = glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  const dvec3 e2 = glm::cross(axis, e1);
  glm::dvec2 sum(0.0);
  for (int i = 0; i < nodes; ++i) {
    const double t = std::tan(top * (i + 0.5) / nodes), theta = 2 * std::atan(width * t);
    const double dtheta_du = 2 * width * top * (1 + t * t) / (1 + width * width * t * t);
    for (int j = 0; j < nodes; ++j) {
      const double phi = 2 * std::numbers::pi * (j + 0.5) / nodes;
      const dvec3 l = std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2);
      sum += ggx_cos_parts(s, l) * (std::sin(theta) * dtheta_du);
    }
  }
  sum *= 2 * std::numbers::pi / (double(nodes) * nodes);
  return c.f0 * sum.x + (1 - c.f0) * sum.y;
}

inline double ltc_sphere_specular(const ltc::Table& table, const SphereCase& c) {
  const glm::dvec2 x = ltc::sphere_integral(ltc::lookup(table, c.roughness, c.v.z), c.v, c.centre, c.radius);
  return c.f0 * x.x + (1 - c.f0) * x.y;
}

}  // namespace nightcap::reference
