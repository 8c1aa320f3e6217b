// What depth.pyramid's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_DEPTH_PYRAMID_GLSL_H
#define NIGHTCAP_DEPTH_PYRAMID_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Texels of the target mip on a side of a workgroup.
NC_CONST(uint, kPyramidGroupSide, 8u)

#define NC_PYRAMID_CONSTANTS_FIELDS(F, A, P)                      \
  /* the level read: depth.linear for level 0 */                  \
  F(ivec2, source_size)                                           \
  F(ivec2, target_size)                                           \
  /* 1: level 0, which reads depth.linear, not the level above */ \
  F(int, from_linear)
NC_PUSH_CONSTANTS(PyramidConstants, NC_PYRAMID_CONSTANTS_FIELDS)

#endif
