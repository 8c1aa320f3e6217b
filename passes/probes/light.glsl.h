// What probes.light's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_PROBES_LIGHT_GLSL_H
#define NIGHTCAP_PROBES_LIGHT_GLSL_H

#include "../core/gpu_layout.glsl.h"

NC_CONST(uint, kProbeLightGroupSide, 8u)

#define NC_PROBE_LIGHT_CONSTANTS_FIELDS(F, A, P)                                   \
  /* lighting.composite's ambient and night sky radiances (rgb) */                 \
  F(vec4, ambient)                                                                 \
  F(vec4, sky)                                                                     \
  /* the level of probes.faces written: 0 lit, each later one the mean of the one  \
     above */                                                                      \
  F(uint, level)                                                                   \
  /* 1 to add the image-based specular's multiple scattering */                    \
  F(uint, multiple_scattering)                                                     \
  /* lighting.deferred's roughness floor and tube samples */                       \
  F(float, min_roughness)                                                          \
  F(int, tube_samples)                                                             \
  /* the sun's shadow filter on shadow.distant: its radius in texels, and the bias \
     and slope limit of shadow.sun_resolve */                                      \
  F(int, filter_radius)                                                            \
  F(float, depth_bias)                                                             \
  F(float, max_slope)
NC_PUSH_CONSTANTS(ProbeLightConstants, NC_PROBE_LIGHT_CONSTANTS_FIELDS)

#endif
