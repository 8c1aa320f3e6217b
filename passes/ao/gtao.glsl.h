// What ao.gtao's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this header
// is read by both compilers).
#ifndef NIGHTCAP_AO_GTAO_GLSL_H
#define NIGHTCAP_AO_GTAO_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Half-resolution pixels on a side of a workgroup.
NC_CONST(uint, kGtaoGroupSide, 8u)
// The most slices and steps a pixel may take (the parameters' ranges).
NC_CONST(int, kGtaoMaxSlices, 16)
NC_CONST(int, kGtaoMaxSteps, 32)
// The disjoint spans one side of a slice keeps above its horizon (docs/frame.md).
NC_CONST(int, kGtaoSpanSlots, 8)

#define NC_GTAO_CONSTANTS_FIELDS(F, A, P)                                                  \
  /* the world-space radius of the search, metres */                                       \
  F(float, radius)                                                                         \
  /* the outer share of the radius over which an occluder's weight falls from 1 to 0 */    \
  F(float, falloff)                                                                        \
  /* the most half-resolution pixels the search reaches from its pixel */                  \
  F(float, max_pixels)                                                                     \
  /* 1: the slices' angles and the steps' offsets follow interleaved gradient noise of the \
     pixel and the frame; 0: every pixel the same (fixed angles, mid-step offsets) */      \
  F(float, noise)                                                                          \
  /* metres behind a visible surface that count as solid, the rest open; 0: all of it */   \
  F(float, thickness)                                                                      \
  /* directions (slices) and horizon samples per side of each slice */                     \
  F(int, slices)                                                                           \
  F(int, steps)
NC_PUSH_CONSTANTS(GtaoConstants, NC_GTAO_CONSTANTS_FIELDS)

#endif
