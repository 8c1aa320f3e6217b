// What ao.temporal's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_AO_TEMPORAL_GLSL_H
#define NIGHTCAP_AO_TEMPORAL_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Half-resolution pixels on a side of a workgroup.
NC_CONST(uint, kAoTemporalGroupSide, 8u)

#define NC_AO_TEMPORAL_CONSTANTS_FIELDS(F, A, P)                                                 \
  /* the most frames the history averages: a still texel's n-th frame weighs 1/n up to 1/this */ \
  F(float, max_frames)                                                                           \
  /* the same where motion.mask marks the texel's footprint (1: the history is rejected) */      \
  F(float, masked_frames)                                                                        \
  /* a history texel is rejected when its depth differs from the one this texel's point had a    \
     frame ago by more than this share of it, plus the depth's change across one texel */        \
  F(float, depth_tolerance)
NC_PUSH_CONSTANTS(AoTemporalConstants, NC_AO_TEMPORAL_CONSTANTS_FIELDS)

#endif
