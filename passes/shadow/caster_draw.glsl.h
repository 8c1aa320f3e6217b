// What the shadow map passes' vertex shaders share with caster_draw.cpp
// (passes/core/gpu_layout.glsl.h says how this header is read by both compilers).
#ifndef NIGHTCAP_SHADOW_CASTER_DRAW_GLSL_H
#define NIGHTCAP_SHADOW_CASTER_DRAW_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_CASTER_CONSTANTS_FIELDS(F, A, P)                                         \
  /* the map drawn: a cascade, a distant level or a local light's cache slot, whose \
     projection the shader reads from the pass's uniform buffer */                  \
  F(uint, layer)
NC_PUSH_CONSTANTS(CasterConstants, NC_CASTER_CONSTANTS_FIELDS)

#endif
