// What exposure's shader shares with exposure.cpp (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_POST_EXPOSURE_GLSL_H
#define NIGHTCAP_POST_EXPOSURE_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of the workgroup that counts them.
NC_CONST(uint, kExposureGroupSide, 16u)
// exposure.histogram's bins: one per invocation of a workgroup, which zeroes them (phase 0) and
// sums them (phase 2) a bin each.
NC_CONST(uint, kExposureBins, kExposureGroupSide* kExposureGroupSide)

#define NC_EXPOSURE_CONSTANTS_FIELDS(F, A, P)                                               \
  F(uint, phase)                                                                            \
  /* the histogram's range; pixels outside count in the end bins */                         \
  F(float, log2_min)                                                                        \
  F(float, log2_max)                                                                        \
  /* the luminance the adapted mean is mapped to; 0: chosen from it */                      \
  F(float, key)                                                                             \
  /* time constant of the adaptation; 0: instant */                                         \
  F(float, adapt_seconds)                                                                   \
  /* Non-zero when every pixel of the lit image holds the same value: texel (0, 0) alone is \
     counted, this many times (the pixel count), and phase 1 is one workgroup. */           \
  F(uint, uniform_pixels)
NC_PUSH_CONSTANTS(ExposureConstants, NC_EXPOSURE_CONSTANTS_FIELDS)

#endif
