// What lighting.tiled's shader shares with its pass and passes/lighting/tiled_layout.h
// (passes/core/gpu_layout.glsl.h says how this header is read by both compilers).
#ifndef NIGHTCAP_LIGHTING_TILED_GLSL_H
#define NIGHTCAP_LIGHTING_TILED_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a tile, a workgroup's: an invocation per pixel.
NC_CONST(uint, kLightingTile, 16u)
NC_CONST(uint, kLightingTileInvocations, kLightingTile* kLightingTile)
// Shaded classes, 1 to 5 (tiled_layout.h names them).
NC_CONST(uint, kLightingTileClasses, 5u)

#define NC_TILED_CONSTANTS_FIELDS(F, A, P)                                                      \
  /* tiles across and down the output */                                                        \
  F(uint, tiles_x)                                                                              \
  F(uint, tiles_y)                                                                              \
  F(float, intensity_scale)                                                                     \
  F(float, min_roughness)                                                                       \
  /* the sun's contact shadows: the ray's length, the depth a hit may span, its steps */        \
  F(float, contact_length)                                                                      \
  F(float, contact_thickness)                                                                   \
  F(uint, contact_steps)                                                                        \
  /* the local lights' moment shadow maps: bias, variance floor, light bleeding, moment bias */ \
  F(float, local_bias)                                                                          \
  F(float, local_min_variance)                                                                  \
  F(float, local_bleeding)                                                                      \
  F(float, local_moment_bias)
NC_PUSH_CONSTANTS(TiledConstants, NC_TILED_CONSTANTS_FIELDS)

#endif
