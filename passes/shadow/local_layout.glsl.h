// The local lights' shadow projections, as shadow.local_plan writes them and the shadow and
// lighting shaders read them (std140; local_layout.h says who hands what to whom, and
// passes/core/gpu_layout.glsl.h how this header is read by both compilers).
#ifndef NIGHTCAP_SHADOW_LOCAL_LAYOUT_GLSL_H
#define NIGHTCAP_SHADOW_LOCAL_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Layers of shadow.local and shadow.local_moments: frame.md's 10-20 slices. The plan's max_maps
// uses at most this many. shadow.local_static has as many cache slots.
NC_CONST(uint, kLocalShadowSlices, 16u)

#define NC_GPU_LOCAL_SHADOWS_FIELDS(F, A, P)                                                       \
  /* Camera-relative world → the map's clip space, a row of the matrix each (the capture's       \
     schema holds arrays of at most 64 numbers): a perspective along the spot's axis, z in         \
     [0, 1] (forward) from `near` to the light's range; w is the distance along that axis. */      \
  A(vec4, clip_x, kLocalShadowSlices)                                                              \
  A(vec4, clip_y, kLocalShadowSlices)                                                              \
  A(vec4, clip_z, kLocalShadowSlices)                                                              \
  A(vec4, clip_w, kLocalShadowSlices)                                                              \
  /* Per map: x near, y far (metres along the axis), z 1 / (far − near), w: the light's index in \
     frame.lights. */                                                                              \
  A(vec4, depth_range, kLocalShadowSlices)                                                         \
  /* x: maps this frame; y: moments per texel in shadow.local_moments, 2 (variance shadow maps)    \
     or 4 (moment shadow maps), from shadow.local_plan's `moments`; z, w: unused. */               \
  F(uvec4, counts)
NC_STRUCT(GpuLocalShadows, NC_GPU_LOCAL_SHADOWS_FIELDS)

// The light-relative world → clip rows of each cache slot's map, what shadow.local_static and
// shadow.local draw with: the casters' draws are relative to the light (its scene.lights
// position), so a static caster's depth does not change with the camera and a slot keeps it
// across frames. Zero for an empty slot.
#define NC_GPU_LOCAL_SHADOW_VIEWS_FIELDS(F, A, P) \
  A(vec4, view_x, kLocalShadowSlices)             \
  A(vec4, view_y, kLocalShadowSlices)             \
  A(vec4, view_z, kLocalShadowSlices)             \
  A(vec4, view_w, kLocalShadowSlices)
NC_STRUCT(GpuLocalShadowViews, NC_GPU_LOCAL_SHADOW_VIEWS_FIELDS)

// Texels on a side of the tile a workgroup of shadow.local_moments blurs and stores.
NC_CONST(uint, kLocalMomentsTile, 16u)

// shadow.local_moments' dispatch: its first layer and its first tile (a map computed again where
// moving casters are).
#define NC_LOCAL_MOMENTS_DISPATCH_FIELDS(F, A, P) \
  F(uint, first_slice)                            \
  F(uint, tile_x)                                 \
  F(uint, tile_y)                                 \
  P(uint, pad)
NC_PUSH_CONSTANTS(LocalMomentsDispatch, NC_LOCAL_MOMENTS_DISPATCH_FIELDS)

#endif
