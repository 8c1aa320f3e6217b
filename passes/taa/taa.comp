#version 460
// taa: this frame's jittered lit colour blended into the history reprojected along
// gbuffer.motion. A still pixel averages its last frames' samples, each drawn at another
// sub-pixel offset, so edges converge to the pixel's coverage. Where something moved (the pixel's
// motion, or motion.mask marking it in this frame or the last: a moving object, hair, foliage,
// frame.md) the history is first clipped, in YCoCg, to what the pixel's 3×3 neighbourhood in this
// frame allows, so that a surface the history saw and this frame does not leaves no ghost; on
// masked pixels the box is tighter and the history shorter. A still pixel's history is not
// clipped (unless clip_still): there a neighbourhood that lacks a sub-pixel line in this frame's
// sample says nothing against the history that averaged it.
#include "../frame/half.glsl"

#include "taa.glsl.h"

layout(local_size_x = kTaaTile, local_size_y = kTaaTile) in;
const int TILE = int(kTaaTile), SPAN = TILE + 2;

layout(set = 0, binding = NC_BINDING(lighting_lit)) uniform sampler2D lit;
layout(set = 0, binding = NC_BINDING(taa_history_previous)) uniform sampler2D history;  // bilinear, clamped
layout(set = 0, binding = NC_BINDING(gbuffer_motion)) uniform sampler2D motion;
layout(set = 0, binding = NC_BINDING(motion_mask)) uniform usampler2D motion_mask;
layout(set = 0, binding = NC_BINDING(motion_mask_previous)) uniform usampler2D previous_mask;
layout(set = 0, binding = NC_BINDING(taa_resolved), rgba16f) uniform writeonly image2D resolved;
layout(set = 0, binding = NC_BINDING(taa_history), rgba16f) uniform writeonly image2D new_history;
layout(push_constant) uniform TaaConstants { NC_BLOCK_MEMBERS(NC_TAA_CONSTANTS_FIELDS) };

shared vec3 neighbourhood[SPAN][SPAN];  // YCoCg of the tile and its apron

// A NaN carries no light and +Inf is the largest half, as in bloom: nothing the resolve stores
// or remembers is non-finite.
vec3 radiance(vec3 c) {
  if (any(isnan(c))) return vec3(0.0);
  return clamp(c, vec3(0.0), vec3(HALF_MAX));
}

vec3 to_ycocg(vec3 c) {
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}
vec3 to_rgb(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

void main() {
  ivec2 size = textureSize(lit, 0);
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * TILE - 1;
  // Outside the image the border pixel repeats: an edge pixel's box holds only what it sees.
  for (int i = int(gl_LocalInvocationIndex); i < SPAN * SPAN; i += TILE * TILE) {
    ivec2 at = ivec2(i % SPAN, i / SPAN);
    neighbourhood[at.y][at.x] = to_ycocg(radiance(texelFetch(lit, clamp(origin + at, ivec2(0), size - 1), 0).rgb));
  }
  barrier();
  ivec2 local = ivec2(gl_LocalInvocationID.xy), p = ivec2(gl_WorkGroupID.xy) * TILE + local;
  if (any(greaterThanEqual(p, size))) return;

  vec3 current_rgb = radiance(texelFetch(lit, p, 0).rgb);
  vec3 current = neighbourhood[local.y + 1][local.x + 1];
  vec3 sum = vec3(0.0), squares = vec3(0.0), lowest = current, highest = current;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 2; ++x) {
      vec3 c = neighbourhood[local.y + y][local.x + x];
      sum += c;
      squares += c * c;
      lowest = min(lowest, c);
      highest = max(highest, c);
    }

  bool masked = texelFetch(motion_mask, p, 0).r != 0u;
  // Where the mask was a frame ago something left: the pixel it uncovered holds its history.
  bool was_masked = texelFetch(previous_mask, p, 0).r != 0u;
  vec2 moved = texelFetch(motion, p, 0).xy;
  bool still = !masked && !was_masked && dot(moved * vec2(size), moved * vec2(size)) < kTaaStillPixels * kTaaStillPixels;
  vec2 history_uv = (vec2(p) + 0.5) / vec2(size) - moved;
  vec4 previous = textureLod(history, history_uv, 0.0);
  // history.a counts the frames it averages; 0: none (frame 0, a camera cut: the graph clears it).
  float frames = previous.a;
  bool inside = all(greaterThanEqual(history_uv, vec2(0.0))) && all(lessThanEqual(history_uv, vec2(1.0)));
  if (!inside || any(isnan(previous)) || any(isinf(previous))) frames = 0.0;

  vec3 centre, extent;
  if (clip == kTaaClipVariance) {
    float box_gamma = masked || was_masked ? masked_gamma : gamma;
    vec3 mean = sum / 9.0, sigma = sqrt(max(squares / 9.0 - mean * mean, vec3(0.0)));
    centre = mean;
    extent = box_gamma * sigma;
  } else {
    centre = 0.5 * (lowest + highest);
    extent = 0.5 * (highest - lowest);
  }
  // A neighbourhood of one hue has no extent along the chroma axes, where the history's halves
  // still differ from the current frame's by their rounding: the box is never thinner than that
  // (2⁻⁹ of the luma), or the rounding would clip away the history of every grey pixel.
  extent = max(extent, vec3(centre.x * (1.0 / 512.0) + 1e-6));
  // Clipped toward the box's centre (Karis 2014): the history keeps its hue where it leaves the box.
  vec3 offset = to_ycocg(radiance(previous.rgb)) - centre;
  vec3 units = abs(offset) / extent;
  float reach = max(units.x, max(units.y, units.z));
  float kept = reach > 1.0 && (!still || clip_still != 0u) ? 1.0 / reach : 1.0;
  vec3 clipped = centre + offset * kept;

  // A clipped history stood for light this frame does not see: it counts for the part of it kept,
  // so a ghost clipped away leaves with its weight instead of fading over the frames it had.
  float accumulated = min(frames * kept + 1.0, masked || was_masked ? masked_max_frames : max_frames);
  // Without history the frame is its lit colour to the bit (finite): frame 0 is a frame without TAA.
  vec3 colour = current_rgb;
  if (frames > 0.0) colour = nearest_half(max(to_rgb(mix(clipped, current, 1.0 / accumulated)), vec3(0.0)));
  // resolved.a: the part of the history's offset from the box centre that clipping removed (0:
  // none); history.a: the frames it now averages, for the next frame's weight.
  imageStore(resolved, p, vec4(colour, frames > 0.0 ? 1.0 - kept : 0.0));
  imageStore(new_history, p, vec4(colour, accumulated));
}
