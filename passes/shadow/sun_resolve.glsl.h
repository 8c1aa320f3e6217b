// What shadow.sun_resolve's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_SHADOW_SUN_RESOLVE_GLSL_H
#define NIGHTCAP_SHADOW_SUN_RESOLVE_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup.
NC_CONST(uint, kSunResolveGroupSide, 8u)

#define NC_SUN_RESOLVE_CONSTANTS_FIELDS(F, A, P)                                    \
  /* texels */                                                                      \
  F(float, depth_bias)                                                              \
  /* metres of light depth per metre across, at most (a receiver nearly edge-on) */ \
  F(float, max_slope)
NC_PUSH_CONSTANTS(ResolveConstants, NC_SUN_RESOLVE_CONSTANTS_FIELDS)

#endif
