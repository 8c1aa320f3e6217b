// What the ambient-occlusion passes share about a half-resolution texel: whether something was
// drawn there, where its depth lies in view space and its normal. Include after
// ../frame/camera.glsl (it reads `camera`) and ../depth/half_footprint.glsl.

#include "chain.glsl.h"

// A depth that marks a surface: positive and below the half's largest value, which the sky
// clamps to (NaN fails both tests).
bool drawn(float depth) { return depth > 0.0 && depth < 65504.0; }

// The view-space point at linear depth `depth` on the ray through full-resolution position
// `pixel`, inverting the (jittered) projection: ndc.x = (P00 x + P20 z) / -z with z = -depth.
vec3 view_point(vec2 pixel, float depth) {
  vec2 ndc = pixel * camera.viewport.zw * 2.0 - 1.0;
  return vec3(depth * (ndc.x + camera.projection[2][0]) / camera.projection[0][0],
              depth * (ndc.y + camera.projection[2][1]) / camera.projection[1][1], -depth);
}

// The full-resolution centre of a half texel's footprint, where its depth is taken to lie.
vec2 footprint_centre(ivec2 half_texel) {
  ivec2 first, last;
  half_footprint(half_texel, ivec2(camera.viewport.xy), first, last);
  return vec2(first + last + 1) * 0.5;
}

// The inverse of footprint_centre: where full-resolution position `pixel` lies in a half image
// of `half_size` texels (texel h's centre at h + 0.5, where its footprint's centre maps). Half of
// it but over the last texel, whose footprint is one pixel wide when the full size is odd.
vec2 half_position(vec2 pixel, ivec2 half_size) {
  vec2 before_last = vec2(2 * half_size) - 3.0;  // the footprint centre of texel half_size - 2
  vec2 last_centre = footprint_centre(half_size - 1);
  vec2 tail = vec2(half_size) - 1.5 + (pixel - before_last) / (last_centre - before_last);
  return mix(pixel * 0.5, tail, greaterThan(pixel, before_last));
}

// What the chain stores where there is nothing to occlude, its images' clear value (chain.glsl.h).
const vec4 kNothingToOcclude = vec4(vec3(kAoZeroComponent), 1.0);

// A world-space vector stored as 0.5·v + 0.5 in an 8-bit texel (normals.half, ao.bent), and
// whether it is one: the zero vector (codes 128) marks a texel where nothing was drawn.
vec3 stored_vector(vec4 texel) { return texel.xyz * 2.0 - 1.0; }
bool is_vector(vec3 v) { return dot(v, v) >= 1e-4; }
