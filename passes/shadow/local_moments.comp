#version 460
// shadow.local_moments: a kLocalMomentsTile² tile of one map's moments, box-blurred (radius BLUR)
// through shared memory: the powers of linear depth for the tile and its apron, then row sums, then
// column sums. The map's edge repeats its last texel. MOMENTS 2: (t, t²) in .rg (variance shadow
// maps); 4: (t, t², t³, t⁴) through local_moments.glsl's quantization transform.
#include "local_moments.glsl"
#include "local_layout.glsl.h"
layout(local_size_x = kLocalMomentsTile, local_size_y = kLocalMomentsTile) in;
layout(constant_id = 0) const int BLUR = 1;
// shadow.local_data's counts.y (the plan's `moments`): a constant, so that the 2-moment variant
// does not pay for the 4-moment one's shared memory and sums on lavapipe.
layout(constant_id = 1) const int MOMENTS = 4;

layout(std140, set = 0, binding = NC_BINDING(shadow_local_data)) uniform LocalBlock { GpuLocalShadows shadows; };
layout(set = 0, binding = NC_BINDING(shadow_local)) uniform sampler2DArray depth_maps;
// Binding 2 is the previous frame's moments, which only the copies of unchanged maps read.
layout(set = 0, binding = NC_BINDING(shadow_local_moments), rgba16) uniform writeonly image2DArray moments_out;

layout(push_constant) uniform LocalMomentsDispatch { NC_BLOCK_MEMBERS(NC_LOCAL_MOMENTS_DISPATCH_FIELDS) };

const int kTile = int(kLocalMomentsTile);
const int kSide = kTile + 2 * BLUR;
// (t, t²) and, with 4 moments, (t³, t⁴): the latter one element long otherwise.
const int kHighSide = MOMENTS == 4 ? kSide : 1;
shared vec2 texel_low[kSide * kSide];
shared vec2 row_low[kTile * kSide];
shared vec2 texel_high[kHighSide * kHighSide];
shared vec2 row_high[kTile * kHighSide];

vec4 stored(vec4 b) { return MOMENTS == 4 ? encode_moments(b) : vec4(b.xy, 0.0, 0.0); }

void main() {
  int slice = int(first_slice + gl_WorkGroupID.z);
  int resolution = textureSize(depth_maps, 0).x;
  ivec2 origin = (ivec2(gl_WorkGroupID.xy) + ivec2(tile_x, tile_y)) * kTile - BLUR;
  uint lane = gl_LocalInvocationIndex;
  vec4 range = shadows.depth_range[slice];
  for (uint i = lane; i < uint(kSide * kSide); i += kLocalMomentsTile * kLocalMomentsTile) {
    ivec2 texel = clamp(origin + ivec2(int(i) % kSide, int(i) / kSide), ivec2(0), ivec2(resolution - 1));
    float d = texelFetch(depth_maps, ivec3(texel, slice), 0).r;
    // Forward perspective depth back to the distance along the axis, then to [0, 1].
    float w = range.x * range.y / max(range.y - d * (range.y - range.x), 1e-30);
    float t = clamp((w - range.x) * range.z, 0.0, 1.0);
    float t2 = t * t;
    texel_low[i] = vec2(t, t2);
    if (MOMENTS == 4) texel_high[i] = vec2(t2 * t, t2 * t2);
  }
  barrier();
  for (uint i = lane; i < uint(kTile * kSide); i += kLocalMomentsTile * kLocalMomentsTile) {
    int x = int(i) % kTile, y = int(i) / kTile;
    vec2 low = vec2(0.0), high = vec2(0.0);
    for (int k = 0; k <= 2 * BLUR; ++k) {
      low += texel_low[y * kSide + x + k];
      if (MOMENTS == 4) high += texel_high[y * kSide + x + k];
    }
    row_low[i] = low;
    if (MOMENTS == 4) row_high[i] = high;
  }
  barrier();
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  vec2 low = vec2(0.0), high = vec2(0.0);
  for (int k = 0; k <= 2 * BLUR; ++k) {
    low += row_low[(local.y + k) * kTile + local.x];
    if (MOMENTS == 4) high += row_high[(local.y + k) * kTile + local.x];
  }
  ivec2 pixel = origin + BLUR + local;
  if (all(lessThan(pixel, ivec2(resolution))))
    imageStore(moments_out, ivec3(pixel, slice), stored(vec4(low, high) / float((2 * BLUR + 1) * (2 * BLUR + 1))));
}
