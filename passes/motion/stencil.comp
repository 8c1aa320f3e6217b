#version 460
// motion.stencil: 1 where a texel within `radius` (a square window, Chebyshev distance) is tagged
// moving, hair or foliage; 0 elsewhere. A workgroup reads its tile and an apron of `radius`
// texels around it into shared memory once, then dilates the rows and the columns of that tile
// separately: 2r + 1 steps each per texel instead of (2r + 1)² texel fetches, which made the
// dilation cost 30 times the fetches of radius 0 at radius 2 (1280×720 on lavapipe).
#include "stencil.glsl.h"

layout(local_size_x = kMotionStencilTile, local_size_y = kMotionStencilTile) in;

layout(set = 0, binding = NC_BINDING(scene_depth)) uniform usampler2D stencil_map;
layout(set = 0, binding = NC_BINDING(motion_mask), r8ui) uniform writeonly uimage2D motion_mask;
layout(push_constant) uniform MotionStencilConstants { NC_BLOCK_MEMBERS(NC_MOTION_STENCIL_CONSTANTS_FIELDS) };

const int TILE = int(kMotionStencilTile), SPAN = TILE + 2 * kMotionStencilMaxRadius;

// passes/scene/scene.h: the classes use bits 0xB5, so road (0x08) and vehicle (0x40) marks OR-ed
// onto a class leave it recognisable.
const uint MOVING = 0x02u, CLASS_BITS = 0xB5u, HAIR = 0x95u, FOLIAGE = 0xA0u;

shared uint tagged_texels[SPAN][SPAN];  // [y][x] of the tile and its apron
shared uint dilated_rows[SPAN][TILE];   // each apron row dilated along x, at the tile's columns

bool tagged(uint stencil) {
  uint tag_class = stencil & CLASS_BITS;
  return (stencil & MOVING) != 0u || tag_class == HAIR || tag_class == FOLIAGE;
}

void main() {
  ivec2 size = textureSize(stencil_map, 0);
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * TILE - radius;
  int span = TILE + 2 * radius;
  int thread = int(gl_LocalInvocationIndex), threads = TILE * TILE;
  // Texels outside the image are untagged: the window is cut at the edges.
  for (int i = thread; i < span * span; i += threads) {
    ivec2 at = ivec2(i % span, i / span), p = origin + at;
    bool inside = all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, size));
    tagged_texels[at.y][at.x] = inside && tagged(texelFetch(stencil_map, p, 0).r) ? 1u : 0u;
  }
  barrier();
  for (int i = thread; i < span * TILE; i += threads) {
    int row = i / TILE, column = i % TILE;
    uint any_tagged = 0u;
    for (int k = 0; k <= 2 * radius; ++k) any_tagged |= tagged_texels[row][column + k];
    dilated_rows[row][column] = any_tagged;
  }
  barrier();
  ivec2 local = ivec2(gl_LocalInvocationID.xy), p = ivec2(gl_WorkGroupID.xy) * TILE + local;
  if (any(greaterThanEqual(p, size))) return;
  uint masked = 0u;
  for (int k = 0; k <= 2 * radius; ++k) masked |= dilated_rows[local.y + k][local.x];
  imageStore(motion_mask, p, uvec4(masked));
}
