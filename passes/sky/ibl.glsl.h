// What the sky's image-based-light passes (sky.cubemap, sky.irradiance, sky.specular) share with
// their shaders and the composite (passes/core/gpu_layout.glsl.h says how this header is read by
// both compilers).
#ifndef NIGHTCAP_SKY_IBL_GLSL_H
#define NIGHTCAP_SKY_IBL_GLSL_H

#include "../core/gpu_layout.glsl.h"

// sky.specular's mips: mip m holds perceptual roughness m / (kSkySpecularMips − 1), so the
// composite reads roughness r at level r · (kSkySpecularMips − 1).
NC_CONST(uint, kSkySpecularMips, 6u)
// Invocations of sky.irradiance's one workgroup.
NC_CONST(uint, kSkyIrradianceGroup, 64u)
// sky.irradiance sums the first level of sky.cubemap no wider than this.
NC_CONST(uint, kSkyIrradianceFace, 32u)

#define NC_SKY_CUBE_CONSTANTS_FIELDS(F, A, P)                           \
  /* the mip level this dispatch writes */                              \
  F(uint, level)                                                        \
  /* 0 when sky.atmosphere wrote no record: the output is left zeros */ \
  F(uint, has_atmosphere)                                               \
  /* sky.specular: GGX samples per texel */                             \
  F(uint, samples)                                                      \
  /* sky.specular and sky.irradiance: the level of sky.cubemap read */  \
  F(uint, source_level)
NC_PUSH_CONSTANTS(SkyCubeConstants, NC_SKY_CUBE_CONSTANTS_FIELDS)

// The sky's irradiance as 9 real spherical-harmonic coefficients (bands 0–2, Ramamoorthi and
// Hanrahan 2001) per colour, already convolved with the clamped cosine and divided by π: the
// radiance a white Lambertian surface of normal n reflects is Σ coefficients[i].rgb · Y_i(n).
// The real spherical harmonics' normalisations (Ramamoorthi and Hanrahan 2001): Y00; Y1m; Y2−2,
// Y2−1, Y21; Y20; Y22 (sh.glsl's sh_basis() and sh_basis_of() below).
NC_CONST(float, kShY00, 0.282094792f)
NC_CONST(float, kShY1, 0.488602512f)
NC_CONST(float, kShY2Cross, 1.092548431f)
NC_CONST(float, kShY20, 0.315391565f)
NC_CONST(float, kShY22, 0.546274215f)

#define NC_GPU_SKY_IRRADIANCE_FIELDS(F, A, P)                                                               \
  /* rgb per basis function, in the order Y00, Y1−1, Y10, Y11, Y2−2, Y2−1, Y20, Y21, Y22; w unused */ \
  A(vec4, coefficients, 9)
NC_STRUCT(GpuSkyIrradiance, NC_GPU_SKY_IRRADIANCE_FIELDS)

#ifdef __cplusplus
#include <array>

namespace nightcap {
// sh.glsl's sh_basis() for the tools: the basis at the unit direction d, in the coefficients' order.
inline std::array<double, 9> sh_basis_of(const glm::dvec3& d) {
  return {kShY00,
          kShY1 * d.y,
          kShY1 * d.z,
          kShY1 * d.x,
          kShY2Cross * d.x * d.y,
          kShY2Cross * d.y * d.z,
          kShY20 * (3.0 * d.z * d.z - 1.0),
          kShY2Cross * d.x * d.z,
          kShY22 * (d.x * d.x - d.y * d.y)};
}
}  // namespace nightcap
#endif

#endif
