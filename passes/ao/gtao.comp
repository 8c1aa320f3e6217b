#version 460
// ao.gtao: ground-truth-based ambient occlusion (Jimenez et al. 2016) at half resolution, one
// invocation per texel of depth.half. Each slice is a plane through the view vector at angle φ
// on screen; along it, each step on either side samples depth.half, the front of a slab
// `thickness` deep along its view ray (0: solid, as plain GTAO's height field), which hides the
// arc between the directions to its front and its back; each direction is hidden by the first
// sample that covers it, by that sample's weight, which falls to 0 as its distance nears the
// radius. The cosine-weighted arcs, about the normal projected into the slice, and their mean
// directions (the bent normal) are integrated in closed form. The visibility is the slices'
// visible arcs over their unoccluded ones.
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
// Whether surfaces are `thickness` deep (thickness > 0), a variant of the pipeline: the slabs'
// spans, compiled in where they are not needed, made the solid case about 30% slower on
// lavapipe.
layout(constant_id = 0) const bool SLABS = false;

const float HALF_PI = 1.57079632679490;
const float kEmptySpan = -2.0;  // below every cosine

// The change of 1/depth per full-resolution pixel at `texel` (1/depth there: `at_texel`; its
// footprint's centre: `texel_centre`) along `axis`, between footprint centres (the last texel of
// an odd size has its centre nearer): the mean of the changes toward its two neighbours where
// they agree, as over a plane (1/depth is linear on screen over a plane); the smaller where they
// do not, the larger being a silhouette; the one there is at the image's edge or beside nothing
// drawn; 0 with neither.
float inverse_depth_slope(ivec2 texel, vec2 texel_centre, ivec2 axis, float at_texel, ivec2 size) {
  ivec2 next = texel + axis, previous = texel - axis;
  float next_depth = all(lessThan(next, size)) ? texelFetch(half_depth, next, 0).r : 0.0;
  float previous_depth = all(greaterThanEqual(previous, ivec2(0))) ? texelFetch(half_depth, previous, 0).r : 0.0;
  bool has_next = drawn(next_depth), has_previous = drawn(previous_depth);
  float centre = dot(texel_centre, vec2(axis));
  float toward_next =
      has_next ? (1.0 / next_depth - at_texel) / (dot(footprint_centre(next), vec2(axis)) - centre) : 0.0;
  float from_previous =
      has_previous ? (at_texel - 1.0 / previous_depth) / (centre - dot(footprint_centre(previous), vec2(axis))) : 0.0;
  if (!has_next || !has_previous) return toward_next + from_previous;
  // Within a quarter of the larger, or the half-float depths' rounding: one plane.
  if (abs(toward_next - from_previous) <= 0.25 * max(abs(toward_next), abs(from_previous)) + 1e-3 * at_texel)
    return 0.5 * (toward_next + from_previous);
  return abs(toward_next) < abs(from_previous) ? toward_next : from_previous;
}

// The view-space point of depth.half at full-resolution position `pixel`, false where nothing
// was drawn there: on the plane of the surface the texel it falls in shows (that texel's 1/depth
// at its footprint's centre and its slope along each axis), evaluated at the position exactly.
// A texel's centre lies up to half a texel off a slice's line, and on a surface seen at a grazing
// angle that point would stand above the surface's tangent in the slice and occlude it.
// Interpolating between the four texels around the position instead would raise a wall across a
// silhouette between two surfaces, which hides what lies behind the nearer one.
bool surface_at(vec2 pixel, ivec2 size, out vec3 point) {
  if (any(lessThan(pixel, vec2(0.0))) || any(greaterThanEqual(pixel, camera.viewport.xy))) return false;
  ivec2 texel = min(ivec2(floor(half_position(pixel, size))), size - 1);
  float depth = texelFetch(half_depth, texel, 0).r;
  if (!drawn(depth)) return false;
  float at_texel = 1.0 / depth;
  vec2 texel_centre = footprint_centre(texel);
  vec2 offset = pixel - texel_centre;
  float inverse = at_texel + inverse_depth_slope(texel, texel_centre, ivec2(1, 0), at_texel, size) * offset.x +
                  inverse_depth_slope(texel, texel_centre, ivec2(0, 1), at_texel, size) * offset.y;
  // Half a texel along a slope steeper than the depth itself (a surface seen edge-on): the texel.
  if (!(inverse > 0.5 * at_texel)) inverse = at_texel;
  point = view_point(pixel, 1.0 / inverse);
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

// slice_arc at angle `angle` (0 … π) from the view vector on side `side` (±1) of the slice.
vec3 arc_on_side(float angle, float cos_angle, float side, float cos_n, float sin_n) {
  return slice_arc(side * angle, cos_angle, side * sqrt(max(1.0 - cos_angle * cos_angle, 0.0)), cos_n, sin_n);
}

// Interleaved gradient noise (Jimenez 2014) in [0, 1).
float gradient_noise(vec2 p) { return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715)))); }

void store(ivec2 texel, vec3 bent_world, float visibility) {
  imageStore(bent_visibility, texel, vec4(bent_world * 0.5 + 0.5, visibility));
}

void store_nothing(ivec2 texel) { imageStore(bent_visibility, texel, kNothingToOcclude); }

// A side of one slice as its steps walk it: from `centre` (full-resolution pixels, where `point`
// lies) along `screen_direction`, out to `screen_radius` half pixels; the view vector; the cosine
// and sine of the angle n from it to the normal projected into the slice.
struct Walk {
  vec2 centre, screen_direction;
  vec3 point, view_dir;
  float screen_radius, step_noise, side;  // side: 1 or −1
  float cos_n, sin_n;
  ivec2 size;
};

// The j-th sample of the walk: true, with its view-space point, the cosine of its direction to
// the view vector and its weight, where it lies on a drawn surface within the radius.
bool occluder(Walk w, int j, out vec3 sample_point, out float cosine, out float weight) {
  // Quadratic spacing: more samples near the pixel, where occluders matter most.
  float t = (float(j) + w.step_noise) / float(steps);
  float offset = max(t * t * w.screen_radius, 1.0);
  if (!surface_at(w.centre + w.side * 2.0 * offset * w.screen_direction, w.size, sample_point)) return false;
  vec3 to_sample = sample_point - w.point;
  float distance = length(to_sample);
  if (distance < 1e-6) return false;
  weight = clamp((radius - distance) / (falloff * radius), 0.0, 1.0);
  cosine = min(dot(to_sample / distance, w.view_dir), 1.0);
  return weight > 0.0;
}

// slice_arc at the direction of cosine `cosine` to the view vector on the walk's side.
vec3 arc_at(Walk w, float cosine) { return arc_on_side(acos(cosine), cosine, w.side, w.cos_n, w.sin_n); }

// What one side's samples hide (slice_arc's integrals, by their weights; `arc_to_tangent`: the
// unoccluded side's) where everything behind a visible surface is solid: each sample above every
// nearer one hides, by its weight, the directions between the previous highest horizon and its
// own, the first surface they pass behind. Directions are held as their cosines to the view
// vector, which fall from 1 there to ∓ sin n at the tangent.
vec3 hidden_below_horizon(Walk w, vec3 arc_to_tangent) {
  float horizon = -w.side * w.sin_n;
  vec3 arc_to_horizon = arc_to_tangent, hidden = vec3(0.0);
  for (int j = 0; j < steps; ++j) {
    vec3 sample_point;
    float cosine, weight;
    if (!occluder(w, j, sample_point, cosine, weight) || cosine <= horizon) continue;
    vec3 arc_to_sample = arc_at(w, cosine);
    hidden += weight * (arc_to_horizon - arc_to_sample);
    horizon = cosine;
    arc_to_horizon = arc_to_sample;
  }
  return hidden;
}

// The same where each sample is the front of a slab `thickness` deep along its view ray, which
// hides the directions between its front and its back: each direction is hidden by the first
// sample that covers it, by that sample's weight, so a sample adds, by its weight, what its span
// adds to the union of the spans before it. The slabs that reach the tangent make a horizon as
// above; the spans above it are kept apart, in kGtaoSpanSlots slots (cosines from > to; an empty
// slot's are below any cosine and meet nothing), with slice_arc at their ends.
vec3 hidden_by_slabs(Walk w, vec3 arc_to_tangent) {
  float horizon = -w.side * w.sin_n;
  vec3 arc_to_horizon = arc_to_tangent, hidden = vec3(0.0);
  float span_from[kGtaoSpanSlots], span_to[kGtaoSpanSlots];
  vec3 arc_from[kGtaoSpanSlots], arc_to[kGtaoSpanSlots];
  for (int i = 0; i < kGtaoSpanSlots; ++i) {
    span_from[i] = kEmptySpan;
    span_to[i] = kEmptySpan;
  }
  for (int j = 0; j < steps; ++j) {
    vec3 sample_point;
    float from, weight;
    if (!occluder(w, j, sample_point, from, weight) || from <= horizon) continue;
    vec3 back_point = sample_point * (1.0 + thickness / -sample_point.z);
    float to = max(dot(normalize(back_point - w.point), w.view_dir), horizon);
    bool reaches_horizon = to == horizon;
    vec3 arc_at_from = arc_at(w, from);
    vec3 arc_at_to = reaches_horizon ? arc_to_horizon : arc_at(w, to);
    // Merge the span with those it meets.
    vec3 merged_away = vec3(0.0);
    for (int i = 0; i < kGtaoSpanSlots; ++i) {
      if (span_to[i] > from || span_from[i] < to) continue;
      merged_away += arc_to[i] - arc_from[i];
      if (span_from[i] > from) {
        from = span_from[i];
        arc_at_from = arc_from[i];
      }
      if (span_to[i] < to) {
        to = span_to[i];
        arc_at_to = arc_to[i];
      }
      span_from[i] = kEmptySpan;
      span_to[i] = kEmptySpan;
    }
    hidden += weight * (arc_at_to - arc_at_from - merged_away);
    if (reaches_horizon) {
      horizon = from;
      arc_to_horizon = arc_at_from;
      continue;
    }
    // Into an empty slot; with none left, into the last, whose span is then forgotten (which
    // takes more than kGtaoSpanSlots disjoint spans on one side).
    bool placed = false;
    for (int i = 0; i < kGtaoSpanSlots; ++i) {
      if (placed || !(span_from[i] == kEmptySpan || i == kGtaoSpanSlots - 1)) continue;
      span_from[i] = from;
      span_to[i] = to;
      arc_from[i] = arc_at_from;
      arc_to[i] = arc_at_to;
      placed = true;
    }
  }
  return hidden;
}

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
  vec2 centre = footprint_centre(texel);  // full-resolution pixels
  vec3 point = view_point(centre, depth);
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
    // Walking out from the pixel on either side, each sample within the radius hides directions
    // of the slice, by its weight (an occluder near the radius hides less of what lies behind it,
    // as for the reference's rays). What no sample hides stays visible up to the tangent.
    float sin_n = sin(n);
    vec3 open = vec3(0.0), occluded = vec3(0.0);  // slice_arc's integrals, tangent to tangent and hidden
    for (int side = 0; side < 2; ++side) {
      Walk w = Walk(centre, screen_direction, point, view_dir, screen_radius, step_noise, side == 0 ? 1.0 : -1.0,
                    cos_n, sin_n, size);
      // On this side the tangent lies at π/2 ± n from the view vector, of cosine ∓ sin n.
      vec3 arc_to_tangent = arc_on_side(HALF_PI + w.side * n, -w.side * sin_n, w.side, cos_n, sin_n);
      open += arc_to_tangent;
      if (SLABS)
        occluded += hidden_by_slabs(w, arc_to_tangent);
      else
        occluded += hidden_below_horizon(w, arc_to_tangent);
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
