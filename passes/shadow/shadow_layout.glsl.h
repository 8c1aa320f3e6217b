// The sun's shadow projections, as shadow.cull and shadow.distant_plan write them and the shadow
// shaders read them (std140; shadow_layout.h says who hands what to whom, and
// passes/core/gpu_layout.glsl.h how this header is read by both compilers).
#ifndef NIGHTCAP_SHADOW_SHADOW_LAYOUT_GLSL_H
#define NIGHTCAP_SHADOW_SHADOW_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

NC_CONST(uint, kShadowCascades, 4u)
NC_CONST(uint, kDistantLevels, 4u)

#define NC_GPU_SHADOW_CASCADES_FIELDS(F, A, P)                                               \
  /* Camera-relative world → the cascade's light clip space: x and y in [-1, 1] across the \
     map, z in [0, 1] from the light's near plane (the scene's side nearest the sun) to its  \
     far one. */                                                                             \
  A(mat4, light_from_world, kShadowCascades)                                                 \
  /* view depth (metres along the view axis) where each cascade ends */                      \
  F(vec4, splits)                                                                            \
  /* a texel's side in metres, per cascade */                                                \
  F(vec4, texel_metres)                                                                      \
  /* metres of light depth that z's [0, 1] spans, per cascade */                             \
  F(vec4, depth_metres)                                                                      \
  /* xyz: the way sunlight travels; w: the map's resolution in texels */                     \
  F(vec4, light_direction)                                                                   \
  /* Per cascade: x, y, the tiles (bit ty·tiles + tx, low word then high) that hold their   \
     casters' depth this frame; z, tiles per side. The resolve reads no other tile. */       \
  A(uvec4, tiles, kShadowCascades)
NC_STRUCT(GpuShadowCascades, NC_GPU_SHADOW_CASCADES_FIELDS)

#define NC_GPU_DISTANT_LEVELS_FIELDS(F, A, P)                                                    \
  /* Camera-relative world → the level's light clip space (as GpuShadowCascades'); z spans the \
     static scene's light depth, the same at every level. */                                     \
  A(mat4, light_from_world, kDistantLevels)                                                      \
  /* a texel's side in metres, per level */                                                      \
  F(vec4, texel_metres)                                                                          \
  /* metres of light depth that z's [0, 1] spans, per level */                                   \
  F(vec4, depth_metres)                                                                          \
  /* xyz: the way sunlight travels; w: the levels' resolution in texels */                       \
  F(vec4, light_direction)                                                                       \
  /* Per level: xy, the texel of the previous frame's level that this frame's texel (0, 0)       \
     covers (the level moved with the camera by whole texels); z, the mask of tiles redrawn      \
     this frame (bit ty·w + tx); w, tiles per side. */                                          \
  A(ivec4, refresh, kDistantLevels)
NC_STRUCT(GpuDistantLevels, NC_GPU_DISTANT_LEVELS_FIELDS)

#endif
