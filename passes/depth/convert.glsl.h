// What depth.convert's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_DEPTH_CONVERT_GLSL_H
#define NIGHTCAP_DEPTH_CONVERT_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Half-resolution pixels on a side of a workgroup.
NC_CONST(uint, kDepthConvertGroupSide, 8u)

#define NC_DEPTH_CONVERT_CONSTANTS_FIELDS(F, A, P)                                 \
  /* the linear depth of the sky (nothing drawn), and the most any pixel stores */ \
  F(float, sky_depth)
NC_PUSH_CONSTANTS(DepthConvertConstants, NC_DEPTH_CONVERT_CONSTANTS_FIELDS)

#endif
