// The reflection probes' dual-paraboloid parameterisation [000][001], one definition for the
// shaders and C++ (passes/core/gpu_layout.glsl.h says how this header is read by both
// compilers). probes.array holds each probe as two square layers: layer 2s + h is slot s's
// hemisphere h, 0 the upper (y ≥ 0), 1 the lower. A point p of a layer in [−1, 1]² (x along the
// texture's width, y down its height) stands for the direction
//   d = (2 p.x, ±(1 − |p|²), 2 p.y) / (1 + |p|²)   (+ for the upper hemisphere),
// a paraboloid's reflection; inverted, p = (d.x, d.z) / (1 + |d.y|). The hemisphere's rim is the
// unit circle; past it (the square's corners) the same formula continues into the other
// hemisphere, so the texels there hold valid directions and bilinear filtering at the rim reads
// the light that is really there.
#ifndef NIGHTCAP_PROBES_PARABOLOID_GLSL_H
#define NIGHTCAP_PROBES_PARABOLOID_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Mips of probes.array: level m is prefiltered for perceptual roughness m / (kProbeArrayMips − 1).
NC_CONST(uint, kProbeArrayMips, 6u)

#ifdef __cplusplus
#include <glm/glm.hpp>

#include <cmath>

namespace nightcap {
inline glm::dvec3 paraboloid_direction(uint32_t hemisphere, glm::dvec2 p) {
  const double r2 = glm::dot(p, p);
  return glm::dvec3(2.0 * p.x, (hemisphere == 0 ? 1.0 : -1.0) * (1.0 - r2), 2.0 * p.y) / (1.0 + r2);
}
inline uint32_t paraboloid_hemisphere(const glm::dvec3& d) { return d.y >= 0.0 ? 0u : 1u; }
inline glm::dvec2 paraboloid_point(const glm::dvec3& d) { return glm::dvec2(d.x, d.z) / (1.0 + std::abs(d.y)); }
}  // namespace nightcap
#else
vec3 paraboloid_direction(uint hemisphere, vec2 p) {
  float r2 = dot(p, p);
  return vec3(2.0 * p.x, (hemisphere == 0u ? 1.0 : -1.0) * (1.0 - r2), 2.0 * p.y) / (1.0 + r2);
}
uint paraboloid_hemisphere(vec3 d) { return d.y >= 0.0 ? 0u : 1u; }
vec2 paraboloid_point(vec3 d) { return d.xz / (1.0 + abs(d.y)); }
#endif

#endif
