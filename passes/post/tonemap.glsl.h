// What tonemap's shaders share with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_POST_TONEMAP_GLSL_H
#define NIGHTCAP_POST_TONEMAP_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_TONEMAP_CONSTANTS_FIELDS(F, A, P)                                 \
  /* multiplies the HDR colour before the curve (with exposure.value's x) */ \
  F(float, exposure)                                                         \
  /* weight of the bloom added to the lit colour */                          \
  F(float, bloom)
NC_PUSH_CONSTANTS(TonemapConstants, NC_TONEMAP_CONSTANTS_FIELDS)

#endif
