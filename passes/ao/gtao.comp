#version 460
// ao.gtao: ground-truth-based ambient occlusion (Jimenez et al. 2016) at half resolution, one
// invocation per texel of depth.half. Each slice is a plane through the view vector at angle φ
// on screen; along it, the steps on either side raise the horizon (the largest cosine to the view
// vector of the direction to a sample of depth.half), and each sample that raises it hides the
// arc it adds, by its weight, which falls to 0 as its distance nears the radius. The
// cosine-weighted arcs, about the normal projected into the slice, and their mean directions (the
// bent normal) are integrated in closed form. The visibility is the slices' visible arcs over
// their unoccluded ones.
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

// Of a slice whose projected normal lies at angle n from the view vector, the integrals from the
// view vector to angle h (either side; h < 0 on the negative one) of the cosine-weighted arc,
// ∫ cos(θ − n)|sin θ| dθ, and of its direction along the slice (x) and toward the viewer (y):
// the visibility and bent normal of the arc between two horizons are differences of these.
// The sines and cosines of h ± n, 2h − n and 3h − n come from those of h and n by the angle-sum
// identities, sparing the shader's transcendentals.
vec3 slice_arc(float h, float cos_h, float sin_h, float cos_n, float sin_n) {
  float cos_2h = 2.0 * cos_h * cos_h - 1.0, sin_2h = 2.0 * sin_h * cos_h;
  float cos_3h = cos_h * (4.0 * cos_h * cos_h - 3.0), sin_3h = sin_h * (3.0 - 4.0 * sin_h * sin_h);
  float cos_2h_minus_n = cos_2h * cos_n + sin_2h * sin_n;
  float sin_h_minus_n = sin_h * cos_n - cos_h * sin_n, sin_h_plus_n = sin_h * cos_n + cos_h * sin_n;
  float cos_h_plus_n = cos_h * cos_n - sin_h * sin_n;
  float sin_3h_minus_n = sin_3h * cos_n - cos_3h * sin_n, cos_3h_minus_n = cos_3h * cos_n + sin_3h * sin_n;
  float arc = (2.0 * h * sin_n - cos_2h_minus_n + cos_n) * 0.25;
  float along = (6.0 * sin_h_minus_n - sin_3h_minus_n - 3.0 * sin_h_plus_n + 8.0 * sin_n) / 12.0;
  float toward = (4.0 * cos_n - cos_3h_minus_n - 3.0 * cos_h_plus_n) / 12.0;
  return vec3(arc, along, toward);
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
    // Walking out from the pixel on either side, a sample within the radius above every nearer
    // one is the first surface the directions between the previous highest horizon and its own
    // pass behind: it hides that arc, by its weight (an occluder near the radius hides less of
    // what lies behind it, as for the reference's rays). What no sample hides stays visible up
    // to the tangent.
    float sin_n = sin(n);
    vec3 open = vec3(0.0), occluded = vec3(0.0);  // slice_arc's integrals, tangent to tangent and hidden
    for (int side = 0; side < 2; ++side) {
      float sign_of_side = side == 0 ? 1.0 : -1.0;
      // The highest horizon so far, starting at the tangent (angle n ± π/2: cosine ∓ sin n, sine
      // ± cos n), and slice_arc there.
      float highest = -sign_of_side * sin_n;
      vec3 arc_to_highest = slice_arc(n + sign_of_side * HALF_PI, highest, sign_of_side * cos_n, cos_n, sin_n);
      open += arc_to_highest;
      for (int j = 0; j < steps; ++j) {
        // Quadratic spacing: more samples near the pixel, where occluders matter most.
        float t = (float(j) + step_noise) / float(steps);
        float offset = max(t * t * screen_radius, 1.0);
        vec3 sample_point;
        if (!surface_at(centre + sign_of_side * offset * screen_direction, size, sample_point)) continue;
        vec3 to_sample = sample_point - point;
        float distance = length(to_sample);
        if (distance < 1e-6) continue;
        float weight = clamp((radius - distance) / (falloff * radius), 0.0, 1.0);
        float cosine = dot(to_sample / distance, view_dir);
        if (weight <= 0.0 || cosine <= highest) continue;
        cosine = min(cosine, 1.0);
        vec3 arc_to_sample = slice_arc(sign_of_side * acos(cosine), cosine, sign_of_side * sqrt(1.0 - cosine * cosine),
                                       cos_n, sin_n);
        occluded += weight * (arc_to_highest - arc_to_sample);
        highest = cosine;
        arc_to_highest = arc_to_sample;
      }
    }
    vec3 visible = open - occluded;
    visibility += projected_length * visible.x;
    unoccluded += projected_length * open.x;
    // Less what the unoccluded arc gives (along 4/3 sin n, toward 2/3 cos n), so that, as for the
    // visibility, the slices' error cancels on an open surface (a control variate).
    bent += projected_length *
            ((visible.y - 4.0 / 3.0 * sin_n) * ortho_direction + (visible.z - 2.0 / 3.0 * cos_n) * view_dir);
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
