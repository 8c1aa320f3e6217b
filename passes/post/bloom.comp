#version 460
// One level of bloom.chain: the 2×2 box average of the level above (the lit colour for level 0)
// blurred by a separable Gaussian. A workgroup computes a kBloomTile² tile: it downsamples the tile
// and an apron of kBloomMaxRadius texels into shared memory, blurs the rows there, then blurs the
// columns and stores — both 1D blurs of the separable filter in one dispatch, the intermediate
// in float rather than rounded to a half. Edges clamp: outside the level, its border texel
// repeats; a source of odd size repeats its last row and column in the box.
#include "../frame/half.glsl"

#include "bloom.glsl.h"

layout(local_size_x = kBloomTile, local_size_y = kBloomTile) in;
const int TILE = int(kBloomTile);
const int SPAN = TILE + 2 * kBloomMaxRadius;

layout(set = 0, binding = NC_BINDING(source)) uniform sampler2D source;  // one mip: texel (0,0) of mip 0 of this view
layout(set = 0, binding = NC_BINDING(bloom_chain), rgba16f) uniform writeonly image2D target;

layout(push_constant) uniform BloomConstants { NC_BLOCK_MEMBERS(NC_BLOOM_CONSTANTS_FIELDS) };

shared vec3 down[SPAN][SPAN];    // the downsampled level over the tile and its apron
shared vec3 across[SPAN][TILE];  // its rows blurred

// A NaN carries no light (tonemap shows it black); +Inf and anything above the half range is
// the largest half, and nothing is negative. Test for NaN before clamp(): its result for a NaN
// operand is undefined.
vec3 radiance(ivec2 p) {
  vec3 c = texelFetch(source, min(p, source_size - 1), 0).rgb;
  if (any(isnan(c))) return vec3(0.0);
  return clamp(c, vec3(0.0), vec3(HALF_MAX));
}

vec3 downsample(ivec2 p) {
  ivec2 q = 2 * clamp(p, ivec2(0), target_size - 1);
  return 0.25 * (radiance(q) + radiance(q + ivec2(1, 0)) + radiance(q + ivec2(0, 1)) + radiance(q + ivec2(1, 1)));
}

void main() {
  const ivec2 tile = ivec2(gl_WorkGroupID.xy) * TILE;
  const int invocations = TILE * TILE;
  for (int i = int(gl_LocalInvocationIndex); i < SPAN * SPAN; i += invocations) {
    ivec2 s = ivec2(i % SPAN, i / SPAN);
    down[s.y][s.x] = downsample(tile - kBloomMaxRadius + s);
  }
  barrier();
  for (int i = int(gl_LocalInvocationIndex); i < SPAN * TILE; i += invocations) {
    ivec2 s = ivec2(i % TILE, i / TILE);
    vec3 sum = weights[0] * down[s.y][s.x + kBloomMaxRadius];
    for (int k = 1; k <= radius; ++k)
      sum += weights[k] * (down[s.y][s.x + kBloomMaxRadius - k] + down[s.y][s.x + kBloomMaxRadius + k]);
    across[s.y][s.x] = sum;
  }
  barrier();
  const ivec2 t = ivec2(gl_LocalInvocationID.xy);
  if (any(greaterThanEqual(tile + t, target_size))) return;
  vec3 sum = weights[0] * across[t.y + kBloomMaxRadius][t.x];
  for (int k = 1; k <= radius; ++k)
    sum += weights[k] * (across[t.y + kBloomMaxRadius - k][t.x] + across[t.y + kBloomMaxRadius + k][t.x]);
  imageStore(target, tile + t, vec4(nearest_half(sum), 1.0));
}
