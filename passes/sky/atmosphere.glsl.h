// The atmosphere the sky's passes share with their shaders (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers): a planet of radius `ground_km` under a shell up to
// `top_km`, holding Rayleigh and Mie scattering that fall off exponentially with height, and
// ozone, which absorbs only, in a layer shaped as a tent around `ozone_centre_km` (Hillaire 2020,
// after Bruneton and Neyret 2008). Lengths in kilometres, coefficients per kilometre.
#ifndef NIGHTCAP_SKY_ATMOSPHERE_GLSL_H
#define NIGHTCAP_SKY_ATMOSPHERE_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Invocations on a side of the workgroups that fill the LUTs.
NC_CONST(uint, kSkyGroupSide, 8u)

#define NC_GPU_ATMOSPHERE_FIELDS(F, A, P)                                                         \
  /* rgb: Rayleigh scattering at sea level; w: its scale height */                                \
  F(vec4, rayleigh)                                                                               \
  /* rgb: Mie scattering at sea level; w: its scale height */                                     \
  F(vec4, mie_scattering)                                                                         \
  /* rgb: Mie extinction (scattering and absorption) at sea level; w: the Cornette-Shanks g */    \
  F(vec4, mie_extinction)                                                                         \
  /* rgb: ozone absorption at the layer's peak; w: the height of the peak */                      \
  F(vec4, ozone)                                                                                  \
  /* x: the ground's radius, y: the atmosphere's top, z: ozone's half width, w: ground albedo */  \
  F(vec4, radii)                                                                                  \
  /* xyz: the way the frame's directional light travels; w: the camera's height in whole metres   \
     (the sky is computed from it: a camera that bobs by millimetres keeps the same sky) */       \
  F(vec4, light)                                                                                  \
  /* rgb: the directional light's radiance (frame.constants' sun_radiance) */                     \
  F(vec4, light_radiance)                                                                         \
  /* x: 1 when this frame's atmosphere differs from the previous frame's (or there was none): the \
     LUTs that depend on it alone are computed again, else kept; y: 1 when the sky seen from the  \
     camera may differ (x, or the light, its radiance or the camera's height changed): sky.view   \
     and the cube maps are computed again, else kept; zw: unused */                               \
  F(uvec4, changed)
NC_STRUCT(GpuAtmosphere, NC_GPU_ATMOSPHERE_FIELDS)

#define NC_SKY_LUT_CONSTANTS_FIELDS(F, A, P)                          \
  /* samples along each ray (sky.view: per ray; sky.transmittance:    \
     midpoints; sky.multiscattering: per direction) */                \
  F(uint, samples)                                                    \
  /* sky.multiscattering: directions per side of its sphere grid */   \
  F(uint, directions)                                                 \
  /* 0 when sky.atmosphere wrote no record (no directional light):    \
     the LUT is left at its clear value, 0, as a skipped pass's is */ \
  F(uint, has_atmosphere)
NC_PUSH_CONSTANTS(SkyLutConstants, NC_SKY_LUT_CONSTANTS_FIELDS)

// sky.aerial_perspective reaches this far from the camera, along each view ray: slice k of N
// ends at kSkyAerialDistanceKm · ((k + 1) / N)², the near slices thin, since most of what a
// street-level frame draws is near. Beyond the last slice, the last slice's air.
NC_CONST(float, kSkyAerialDistanceKm, 32.0f)

#endif
