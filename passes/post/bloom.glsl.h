// What bloom's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_POST_BLOOM_GLSL_H
#define NIGHTCAP_POST_BLOOM_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup's tile.
NC_CONST(uint, kBloomTile, 16u)
// The widest blur: the apron a workgroup loads around its tile (sigma's maximum keeps ceil(3 sigma)
// within it).
NC_CONST(int, kBloomMaxRadius, 8)

#define NC_BLOOM_CONSTANTS_FIELDS(F, A, P)                                \
  /* the level read (the lit colour for level 0) and the level written */ \
  F(ivec2, source_size)                                                   \
  F(ivec2, target_size)                                                   \
  /* at most kBloomMaxRadius */                                           \
  F(int, radius)                                                          \
  /* weights[k] for offsets ±k, summing to 1 over -radius..radius */     \
  A(float, weights, kBloomMaxRadius + 1)
NC_PUSH_CONSTANTS(BloomConstants, NC_BLOOM_CONSTANTS_FIELDS)

#endif
