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

// lighting.tile_classes: per shaded class, its VkDispatchIndirectCommand (x: the class's tiles;
// y = z = 1, or all 0 when it has none) and in w the first entry of its list in
// lighting.tile_lists.
#define NC_TILE_CLASSES_FIELDS(F, A, P) \
  /* class 1 */                         \
  F(uvec4, directional)                 \
  /* class 2 */                         \
  F(uvec4, local)                       \
  /* class 3 */                         \
  F(uvec4, tube)                        \
  /* class 4 */                         \
  F(uvec4, sphere)                      \
  /* class 5 */                         \
  F(uvec4, sphere_and_tube)
NC_STRUCT(GpuTileClasses, NC_TILE_CLASSES_FIELDS)

// lighting.tile_lists, entry i: the class of tile i (row-major: y · tiles across + x), and the
// i-th tile of the lists (class 1's, then 2's, and so on to 5's, each in row-major order); 0 past
// the tiles.
#define NC_TILE_ENTRY_FIELDS(F, A, P) \
  F(uint, tile_class)                 \
  F(uint, listed_tile)
NC_STRUCT(GpuTileEntry, NC_TILE_ENTRY_FIELDS)

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
