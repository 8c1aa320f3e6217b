#version 460
// ao.gtao: ground-truth-based ambient occlusion (Jimenez et al. 2016) at half resolution, one
// invocation per texel of depth.half. Each slice is a plane through the view vector at angle φ
// on screen; along it, the steps on either side find the highest horizon (the largest cosine to
// the view vector of the direction to a sample of depth.half), each sample weighted down to the
// lowest horizon as its distance nears the radius; the cosine-weighted visible arc between the
// two horizons, about the normal projected into the slice, is integrated in closed form, and so is
// the mean direction of that arc (the bent normal). The visibility is the slices' visible arcs
// over their unoccluded ones.
#include "../depth/half_footprint.glsl"
#include "../frame/types.glsl"
#include "gtao.glsl.h"

layout(local_size_x = kGtaoGroupSide, local_size_y = kGtaoGroupSide) in;

#include "../frame/camera.glsl"
#include "half_view.glsl"
layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(set = 0, binding = NC_BINDING(depth_half)) uniform sampler2D half_depth;
layout(set = 0, binding = NC_BINDING(normals_half)) uniform sampler2D half_normals;
layout(set = 0, binding = NC_BINDING(ao_raw), rgba8) uniform writeonly image2D bent_visibility;
layout(push_constant) uniform GtaoConstants { NC_BLOCK_MEMBERS(NC_GTAO_CONSTANTS_FIELDS) };

const float HALF_PI = 1.57079632679490;

// The view-space point of depth.half at `position` (half-resolution texel units, a texel's centre
// at i + 0.5), false where nothing was drawn there. On the slice's line exactly: a texel's centre
// lies up to half a texel off it, and on a surface seen at a grazing angle that point would stand
// above the surface's tangent in the slice and occlude it. Where the four texels around the
// position lie on one plane (1/depth, linear on screen over a plane, untwisted across them, and
// no step) the depth is interpolated so; elsewhere (an edge, a crease) the nearest texel's point
// is taken, as XeGTAO does.
bool surface_at(vec2 position, ivec2 size, out vec3 point) {
  ivec2 nearest = ivec2(floor(position));
  if (any(lessThan(nearest, ivec2(0))) || any(greaterThanEqual(nearest, size))) return false;
  // The four texel centres around the position; within half a texel of the image's edge, the
  // two nearest the edge and a weight outside [0, 1]: 1/depth extrapolates, exactly over a plane.
  vec2 below = position - 0.5;
  ivec2 first = clamp(ivec2(floor(below)), ivec2(0), max(size - 2, ivec2(0))), last = min(first + 1, size - 1);
  vec2 f = below - vec2(first);
  float d00 = texelFetch(half_depth, first, 0).r, d10 = texelFetch(half_depth, ivec2(last.x, first.y), 0).r;
  float d01 = texelFetch(half_depth, ivec2(first.x, last.y), 0).r, d11 = texelFetch(half_depth, last, 0).r;
  // An image one texel wide or high has no neighbour to interpolate toward.
  if (all(greaterThan(size, ivec2(1))) && drawn(d00) && drawn(d10) && drawn(d01) && drawn(d11)) {
    vec4 inverse = 1.0 / vec4(d00, d10, d01, d11);
    float largest = max(max(inverse.x, inverse.y), max(inverse.z, inverse.w));
    float smallest = min(min(inverse.x, inverse.y), min(inverse.z, inverse.w));
    float twist = abs(inverse.x + inverse.w - inverse.y - inverse.z);
    // A step between two surfaces is untwisted along its edge: the depths must also stay within
    // a factor of two.
    if (twist <= 0.01 * largest && largest <= 2.0 * smallest) {
      float depth = 1.0 / mix(mix(inverse.x, inverse.y, f.x), mix(inverse.z, inverse.w, f.x), f.y);
      point = view_point(position * 2.0, depth);
      return true;
    }
  }
  float depth = texelFetch(half_depth, nearest, 0).r;
  if (!drawn(depth)) return false;
  point = view_point(footprint_centre(nearest), depth);
  return true;
}

// Interleaved gradient noise (Jimenez 2014) in [0, 1).
float gradient_noise(vec2 p) { return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715)))); }

void store(ivec2 texel, vec3 bent_world, float visibility) {
  imageStore(bent_visibility, texel, vec4(bent_world * 0.5 + 0.5, visibility));
}

void store_nothing(ivec2 texel) { imageStore(bent_visibility, texel, kNothingToOcclude); }

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = textureSize(half_depth, 0);
  if (any(greaterThanEqual(texel, size))) return;
  float depth = texelFetch(half_depth, texel, 0).r;
  vec3 stored = stored_vector(texelFetch(half_normals, texel, 0));  // the best-fit normal, unnormalised
  // Nothing drawn (the sky, a cleared target, a NaN depth): nothing to occlude.
  if (!drawn(depth) || !is_vector(stored)) {
    store_nothing(texel);
    return;
  }
  mat3 view_from_world = mat3(camera.view);
  vec3 normal = normalize(view_from_world * normalize(stored));
  vec3 point = view_point(footprint_centre(texel), depth);
  vec3 view_dir = normalize(-point);

  // The radius on screen, in half-resolution pixels: metres × pixels per metre at this depth.
  float pixels_per_metre = 0.25 * camera.viewport.y * abs(camera.projection[1][1]) / depth;
  float screen_radius = min(radius * pixels_per_metre, max_pixels);
  if (screen_radius < 1.0) {  // the radius spans under a pixel: no sample to take
    store(texel, transpose(view_from_world) * normal, 1.0);
    return;
  }

  float frame_offset = 5.588238 * float(frame.counts.y % 64u);
  float slice_noise = noise > 0.0 ? gradient_noise(vec2(texel) + frame_offset) : 0.0;
  float step_noise = noise > 0.0 ? gradient_noise(vec2(texel.y, texel.x) + 0.5 * frame_offset + 17.0) : 0.5;
  vec2 centre = vec2(texel) + 0.5;
  float visibility = 0.0, unoccluded = 0.0;
  vec3 bent = vec3(0.0);
  for (int s = 0; s < slices; ++s) {
    float phi = (float(s) + slice_noise) * PI / float(slices);
    vec3 direction = vec3(cos(phi), sin(phi), 0.0);
    // On screen, y grows downward while view-space y grows upward (the projection flips it).
    vec2 screen_direction = vec2(direction.x, -direction.y);
    vec3 ortho_direction = normalize(direction - dot(direction, view_dir) * view_dir);
    vec3 axis = cross(ortho_direction, view_dir);
    vec3 projected_normal = normal - axis * dot(normal, axis);
    float projected_length = length(projected_normal);
    if (projected_length < 1e-6) continue;  // the slice's plane is the surface's own
    float cos_n = clamp(dot(projected_normal, view_dir) / projected_length, -1.0, 1.0);
    float n = sign(dot(ortho_direction, projected_normal)) * acos(cos_n);
    // Each side's horizon starts at the surface's tangent, the lowest it can be.
    float low_positive = cos(n + HALF_PI), low_negative = cos(n - HALF_PI);
    float horizon_positive = low_positive, horizon_negative = low_negative;
    for (int j = 0; j < steps; ++j) {
      // Quadratic spacing: more samples near the pixel, where occluders matter most.
      float t = (float(j) + step_noise) / float(steps);
      float offset = max(t * t * screen_radius, 1.0);
      for (int side = 0; side < 2; ++side) {
        vec3 sample_point;
        if (!surface_at(centre + (side == 0 ? offset : -offset) * screen_direction, size, sample_point)) continue;
        vec3 to_sample = sample_point - point;
        float distance = length(to_sample);
        if (distance < 1e-6) continue;
        float weight = clamp((radius - distance) / (falloff * radius), 0.0, 1.0);
        float cosine = dot(to_sample / distance, view_dir);
        if (side == 0)
          horizon_positive = max(horizon_positive, mix(low_positive, cosine, weight));
        else
          horizon_negative = max(horizon_negative, mix(low_negative, cosine, weight));
      }
    }
    // The horizons as angles from the view vector, kept within the hemisphere about n.
    float h0 = -acos(clamp(horizon_negative, -1.0, 1.0)), h1 = acos(clamp(horizon_positive, -1.0, 1.0));
    h0 = n + max(h0 - n, -HALF_PI);
    h1 = n + min(h1 - n, HALF_PI);
    float sin_n = sin(n);
    // ∫ cos(θ - n)|sin θ| dθ from h0 to h1 (the cosine-weighted visible arc of the slice).
    float arc0 = (cos_n + 2.0 * h0 * sin_n - cos(2.0 * h0 - n)) * 0.25;
    float arc1 = (cos_n + 2.0 * h1 * sin_n - cos(2.0 * h1 - n)) * 0.25;
    visibility += projected_length * (arc0 + arc1);
    // The same arc with nothing in the way (h0, h1 = n ∓ π/2).
    unoccluded += projected_length * (cos_n + n * sin_n);
    // The arc's mean direction, in the slice's frame (along ortho_direction, along view_dir).
    float along = (6.0 * sin(h0 - n) - sin(3.0 * h0 - n) + 6.0 * sin(h1 - n) - sin(3.0 * h1 - n) + 16.0 * sin_n -
                   3.0 * (sin(h0 + n) + sin(h1 + n))) /
                  12.0;
    float toward = (-cos(3.0 * h0 - n) - cos(3.0 * h1 - n) + 8.0 * cos_n - 3.0 * (cos(h0 + n) + cos(h1 + n))) / 12.0;
    // Less what the unoccluded arc gives (along 4/3 sin n, toward 2/3 cos n), so that, as for the
    // visibility, the slices' error cancels on an open surface (a control variate).
    bent += projected_length * ((along - 4.0 / 3.0 * sin_n) * ortho_direction + (toward - 2.0 / 3.0 * cos_n) * view_dir);
  }
  // Over every angle φ, the unoccluded arcs average 1; over a few slices they do not, and their
  // ratio to it (rather than a plain mean that a clamp at 1 would bias) makes an open surface
  // exactly 1 however few the slices.
  visibility = unoccluded > 0.0 ? clamp(visibility / unoccluded, 0.0, 1.0) : 1.0;
  // Over every angle the unoccluded arcs' mean direction is 2/3 n (the cosine-weighted hemisphere's).
  bent = 2.0 / 3.0 * normal + bent / float(slices);
  vec3 bent_view = dot(bent, bent) > 1e-12 ? normalize(bent) : normal;
  store(texel, transpose(view_from_world) * bent_view, visibility);
}
