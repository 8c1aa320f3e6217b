// What taa's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this header is
// read by both compilers).
#ifndef NIGHTCAP_TAA_GLSL_H
#define NIGHTCAP_TAA_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup's tile; it loads the lit colour of the tile and a one-pixel
// apron, the 3×3 neighbourhoods of its pixels, once.
NC_CONST(uint, kTaaTile, 16u)

// How the reprojected history is limited to what the current frame's neighbourhood allows.
NC_CONST(uint, kTaaClipVariance, 0u)  // the box mean ± gamma·sigma (Salvi 2016)
NC_CONST(uint, kTaaClipMinMax, 1u)    // the box of the neighbourhood's minimum and maximum

// A pixel that moves less than this (pixels) with its surface, unmasked now and a frame ago, is
// still: its history is not clipped unless clip_still.
NC_CONST(float, kTaaStillPixels, 1.0 / 64.0)

#define NC_TAA_CONSTANTS_FIELDS(F, A, P)                                                  \
  /* the most frames the history averages: the current frame weighs 1/n after n frames */ \
  F(float, max_frames)                                                                    \
  /* the same where motion.mask is set */                                                 \
  F(float, masked_max_frames)                                                             \
  /* the variance box's half size in standard deviations; where motion.mask is set */     \
  F(float, gamma)                                                                         \
  F(float, masked_gamma)                                                                  \
  /* kTaaClip* */                                                                         \
  F(uint, clip)                                                                           \
  /* 1: clip the history of still pixels too */                                           \
  F(uint, clip_still)
NC_PUSH_CONSTANTS(TaaConstants, NC_TAA_CONSTANTS_FIELDS)

#endif
