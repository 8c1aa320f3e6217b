// What ao.filter's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this header
// is read by both compilers).
#ifndef NIGHTCAP_AO_FILTER_GLSL_H
#define NIGHTCAP_AO_FILTER_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Half-resolution pixels on a side of a workgroup.
NC_CONST(uint, kAoFilterGroupSide, 8u)
// The largest radius of the filter's window, in half-resolution pixels (the parameter's range).
NC_CONST(int, kAoFilterMaxRadius, 4)

#define NC_AO_FILTER_CONSTANTS_FIELDS(F, A, P)                                               \
  /* the window is (2·radius + 1)² half-resolution pixels; 0: a copy */                    \
  F(int, radius)                                                                             \
  /* a neighbour weighs nothing once it lies this share of the pixel's depth off the pixel's \
     tangent plane */                                                                        \
  F(float, plane_tolerance)                                                                  \
  /* a neighbour's weight is the cosine between the two normals to this power */             \
  F(float, normal_power)
NC_PUSH_CONSTANTS(AoFilterConstants, NC_AO_FILTER_CONSTANTS_FIELDS)

#endif
