#version 460
// ao.temporal: one invocation per half-resolution texel blends ao.filtered into the history,
// reprojected along motion.half (gbuffer.motion at the texel depth.half took its depth from). The
// history is read at the four texels around the reprojected position, each weighted bilinearly
// and kept only where its depth a frame ago agrees with where this texel's surface point was then
// (the previous view-projection of its point): a surface uncovered this frame, or seen across an
// edge, takes no history from what covered it. Where motion.mask marks the footprint (a moving
// object, hair, foliage) the history is as short as masked_frames allows.
#include "../depth/half_footprint.glsl"
#include "../frame/types.glsl"
#include "temporal.glsl.h"

layout(local_size_x = kAoTemporalGroupSide, local_size_y = kAoTemporalGroupSide) in;

#include "../frame/camera.glsl"
#include "half_view.glsl"
layout(set = 0, binding = NC_BINDING(ao_filtered)) uniform sampler2D current;
layout(set = 0, binding = NC_BINDING(ao_history_previous)) uniform sampler2D history;
layout(set = 0, binding = NC_BINDING(depth_half)) uniform sampler2D half_depth;
layout(set = 0, binding = NC_BINDING(depth_half_previous)) uniform sampler2D previous_depth;
layout(set = 0, binding = NC_BINDING(motion_half)) uniform sampler2D half_motion;
layout(set = 0, binding = NC_BINDING(motion_mask)) uniform usampler2D motion_mask;
layout(set = 0, binding = NC_BINDING(ao_bent), rgba8) uniform writeonly image2D bent_visibility;
layout(set = 0, binding = NC_BINDING(ao_history), rgba16f) uniform writeonly image2D new_history;
layout(push_constant) uniform AoTemporalConstants { NC_BLOCK_MEMBERS(NC_AO_TEMPORAL_CONSTANTS_FIELDS) };

// The depth's change from `texel` to the nearer-valued of its two neighbours along `axis`: how
// much a history texel a texel away may differ on the same surface. 0 with no drawn neighbour.
float depth_change(ivec2 texel, ivec2 axis, ivec2 size, float depth) {
  float change = 65504.0;
  for (int side = -1; side <= 1; side += 2) {
    ivec2 at = clamp(texel + side * axis, ivec2(0), size - 1);
    float neighbour = texelFetch(half_depth, at, 0).r;
    if (at != texel && drawn(neighbour)) change = min(change, abs(neighbour - depth));
  }
  return change < 65504.0 ? change : 0.0;
}

bool masked_footprint(ivec2 texel) {
  ivec2 first, last;
  half_footprint(texel, ivec2(camera.viewport.xy), first, last);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x)
      if (texelFetch(motion_mask, ivec2(x, y), 0).r != 0u) return true;
  return false;
}

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = textureSize(half_depth, 0);
  if (any(greaterThanEqual(texel, size))) return;
  float depth = texelFetch(half_depth, texel, 0).r;
  vec4 now = texelFetch(current, texel, 0);
  vec3 now_bent = stored_vector(now);
  // Nothing drawn: unoccluded, and no history.
  if (!drawn(depth) || !is_vector(now_bent)) {
    imageStore(bent_visibility, texel, kNothingToOcclude);
    imageStore(new_history, texel, vec4(0.0));
    return;
  }

  vec2 centre = footprint_centre(texel);
  vec3 point = view_point(centre, depth);
  vec3 world = transpose(mat3(camera.view)) * point + camera.eye.xyz;
  float then = (camera.previous_view_projection * vec4(world, 1.0)).w;  // its linear depth a frame ago
  float tolerance = depth_tolerance * then + max(depth_change(texel, ivec2(1, 0), size, depth),
                                                 depth_change(texel, ivec2(0, 1), size, depth));
  // The reprojected position in half texels (a texel's centre at i + 0.5).
  vec2 moved = texelFetch(half_motion, texel, 0).xy;
  vec2 position = half_position(centre - moved * camera.viewport.xy, size);
  vec2 below = position - 0.5;
  ivec2 first = ivec2(floor(below));
  vec2 f = below - vec2(first);

  float kept = 0.0, frames = 0.0, visibility = 0.0;
  vec3 direction = vec3(0.0);
  for (int i = 0; i < 4; ++i) {
    ivec2 at = first + ivec2(i & 1, i >> 1);
    float weight = ((i & 1) != 0 ? f.x : 1.0 - f.x) * ((i >> 1) != 0 ? f.y : 1.0 - f.y);
    if (weight <= 0.0 || any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, size))) continue;
    float was = texelFetch(previous_depth, at, 0).r;
    vec4 past = texelFetch(history, at, 0);
    float past_frames = length(past.xyz);
    // No history there (frame 0, a camera cut, the sky; NaN or Inf, which no frame writes), or another
    // surface's.
    if (!drawn(was) || abs(was - then) > tolerance || !(past_frames >= 0.5) || any(isnan(past)) || any(isinf(past)))
      continue;
    kept += weight;
    frames += weight * past_frames;
    visibility += weight * past.a;
    direction += weight * past.xyz / past_frames;
  }

  float limit = masked_footprint(texel) ? masked_frames : max_frames;
  // The history's texels that agree stand for the frames they average, in proportion to the part
  // of the bilinear weight they hold.
  float accumulated = min(frames + 1.0, limit);
  float own = 1.0 / accumulated;
  vec3 bent = normalize(now_bent);
  float blended = now.a;
  if (kept > 0.0) {
    blended = mix(visibility / kept, now.a, own);
    vec3 mixed = mix(direction / kept, bent, own);
    if (is_vector(mixed)) bent = normalize(mixed);
  }
  blended = clamp(blended, 0.0, 1.0);
  imageStore(bent_visibility, texel, vec4(bent * 0.5 + 0.5, blended));
  imageStore(new_history, texel, vec4(bent * accumulated, blended));
}
