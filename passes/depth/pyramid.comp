#version 460
// One level of the min-max depth pyramid. Level 0 reads depth.linear (a 2×2 footprint, the
// level being half the full size rounded up); later levels read the level above. Where the
// level above has an odd size, its last row/column is folded into the last texel (a 3-wide
// footprint) so no source texel is ever dropped: the pyramid stays conservative.
#include "pyramid.glsl.h"

layout(local_size_x = kPyramidGroupSide, local_size_y = kPyramidGroupSide) in;

layout(set = 0, binding = NC_BINDING(depth_linear)) uniform sampler2D linear_depth;
layout(set = 0, binding = NC_BINDING(depth_pyramid), rg32f) uniform readonly image2D source_level;
layout(set = 0, binding = NC_BINDING(depth_pyramid) + 1, rg32f) uniform writeonly image2D target_level;

layout(push_constant) uniform PyramidConstants { NC_BLOCK_MEMBERS(NC_PYRAMID_CONSTANTS_FIELDS) };

vec2 fetch(ivec2 p) {
  if (from_linear != 0) {
    float d = texelFetch(linear_depth, p, 0).r;
    return vec2(d, d);
  }
  return imageLoad(source_level, p).rg;
}

void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(t, target_size))) return;
  ivec2 first = 2 * t;
  ivec2 last = min(2 * t + 1, source_size - 1);
  if (t.x == target_size.x - 1) last.x = source_size.x - 1;
  if (t.y == target_size.y - 1) last.y = source_size.y - 1;
  vec2 result = vec2(3.0e38, -3.0e38);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      vec2 v = fetch(ivec2(x, y));
      result = vec2(min(result.x, v.x), max(result.y, v.y));
    }
  imageStore(target_level, t, vec4(result, 0.0, 0.0));
}
