// What lights.cluster's shader shares with C++ (cluster_layout.h says how froxels divide the
// view; passes/core/gpu_layout.glsl.h how this header is read by both compilers).
#ifndef NIGHTCAP_LIGHTS_CLUSTER_LAYOUT_GLSL_H
#define NIGHTCAP_LIGHTS_CLUSTER_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Tiles on a side of a block: lights.cluster lists the lights that reach each block first, and a
// tile tests only its block's.
NC_CONST(uint, kClusterBlock, 4u)

// lights.cluster_stats: what the lists hold, what the caps cut and how the depth was sliced. Sums
// saturate at 2^32 − 1.
#define NC_GPU_CLUSTER_STATS_FIELDS(F, A, P)                                                     \
  /* local lights of frame.lights (point, spot, tube) */                                         \
  F(uint, lights)                                                                                \
  /* tiles_x · tiles_y · slices */                                                             \
  F(uint, froxels)                                                                               \
  /* froxels that at least one light reaches */                                                  \
  F(uint, froxels_lit)                                                                           \
  /* indices stored */                                                                           \
  F(uint, entries)                                                                               \
  /* indices the lists would hold without caps */                                                \
  F(uint, entries_wanted)                                                                        \
  /* the longest list, before the caps */                                                        \
  F(uint, max_count)                                                                             \
  /* froxels with more lights than max_lights_per_froxel */                                      \
  F(uint, froxels_over_cap)                                                                      \
  /* entries those lost (the lights of highest index) */                                         \
  F(uint, dropped_over_cap)                                                                      \
  /* froxels that lost entries to the index capacity (the last in froxel order: farthest slice   \
     first), and the entries they lost */                                                        \
  F(uint, froxels_cut)                                                                           \
  F(uint, dropped_cut)                                                                           \
  /* the limits applied */                                                                       \
  F(uint, per_froxel_cap)                                                                        \
  F(uint, index_capacity)                                                                        \
  /* The froxels' shape (lights.cluster's parameters): lighting finds a pixel's froxel by it. */ \
  F(float, max_distance)                                                                         \
  F(uint, tile_size)                                                                             \
  F(uint, slices)
NC_STRUCT(GpuClusterStats, NC_GPU_CLUSTER_STATS_FIELDS)

#define NC_CLUSTER_CONSTANTS_FIELDS(F, A, P)                               \
  F(uint, max_per_froxel)                                                  \
  F(uint, max_indices)                                                     \
  /* the level of depth.pyramid whose texel covers a tile (or its last) */ \
  F(int, pyramid_level)                                                    \
  F(float, max_distance)                                                   \
  F(uint, tiles_x)                                                         \
  F(uint, tiles_y)                                                         \
  F(uint, max_block_lights)
NC_PUSH_CONSTANTS(ClusterConstants, NC_CLUSTER_CONSTANTS_FIELDS)

#endif
