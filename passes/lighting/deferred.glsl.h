// What lighting.deferred's shaders share with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_LIGHTING_DEFERRED_GLSL_H
#define NIGHTCAP_LIGHTING_DEFERRED_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_DEFERRED_CONSTANTS_FIELDS(F, A, P) \
  F(float, intensity_scale)                   \
  F(float, min_roughness)                     \
  F(int, tube_samples)
NC_PUSH_CONSTANTS(DeferredConstants, NC_DEFERRED_CONSTANTS_FIELDS)

#endif
