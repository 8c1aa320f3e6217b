// The top-down map's projection, as shadow.topdown_plan writes it and shadow.topdown and the
// shaders that judge sky visibility read it (std140; passes/core/gpu_layout.glsl.h says how
// this header is read by both compilers).
#ifndef NIGHTCAP_SHADOW_TOPDOWN_LAYOUT_GLSL_H
#define NIGHTCAP_SHADOW_TOPDOWN_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_GPU_TOPDOWN_FIELDS(F, A, P)                                                         \
  /* Camera-relative world → the map's clip space: x across world x and y across world z, in \
     [-1, 1] over the map's square; z in [0, 1] from the static scene's top down to its        \
     bottom. */                                                                                \
  F(mat4, map_from_world)                                                                      \
  /* x: a texel's side in metres; y: metres of height z's [0, 1] spans; z: texels per side;    \
     w: metres a surface point is pushed along its normal before it looks up (past the texel   \
     its own wall or roof edge falls in). */                                                   \
  F(vec4, extent)
NC_STRUCT(GpuTopdown, NC_GPU_TOPDOWN_FIELDS)

#endif
