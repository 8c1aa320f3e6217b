// What motion.stencil's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_MOTION_STENCIL_GLSL_H
#define NIGHTCAP_MOTION_STENCIL_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup's tile.
NC_CONST(uint, kMotionStencilTile, 16u)
// The widest apron around a tile that the shader's shared memory holds: the radius's maximum.
NC_CONST(int, kMotionStencilMaxRadius, 16)

#define NC_MOTION_STENCIL_CONSTANTS_FIELDS(F, A, P)         \
  /* pixels of dilation, at most kMotionStencilMaxRadius */ \
  F(int, radius)
NC_PUSH_CONSTANTS(MotionStencilConstants, NC_MOTION_STENCIL_CONSTANTS_FIELDS)

#endif
