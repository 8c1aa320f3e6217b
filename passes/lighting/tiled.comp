#version 460
// lighting.tiled: direct light per 16×16-pixel tile from the froxel lists of lights.cluster, in
// seven dispatches of one pass (passes/lighting/tiled_layout.h names the classes):
//   0: a workgroup per tile classifies it (unlit, directional only, local point and spot lights,
//      with tubes, with spheres, with both) into lighting.tile_lists, writes an unlit tile's
//      outputs (0) at once, and zeroes the entries past the last tile;
//   1: one workgroup lists the tiles of classes 1 to 5 in row-major order (each invocation a
//      run of tiles, offsets from the runs' counts) and writes each class's indirect dispatch;
//   2 to 6: a workgroup per listed tile of class 1, 2, … 5, shades its pixels.
// Nothing depends on execution order (the classification ORs flags, the lists come from integer
// sums), and each pixel is shaded the same way whatever the order: every run writes the same
// bytes.
//
// Shading follows lighting.deferred (brdf.glsl, the same roughness floor and range window, point
// and spot lights bit for bit its arithmetic) for the sun, directional lights and the local
// lights of the pixel's froxel, in ascending index. A point light with a radius is a sphere:
// Lambert's illuminance of a sphere cut by the horizon, LTC for its specular. A tube is a line
// of candela per metre: its diffuse integrated along the segment (ltc_lambert_line), its
// specular by LTC (ltc_tube). The sun's shadow is shadow.sun's red channel (shadow.sun_resolve)
// times its contact shadow, a short march here (contact_shadow). A spot light with a map in
// shadow.local_moments is shadowed by it (local_visibility: 4MSM or VSM).
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "../lights/cluster_layout.glsl.h"
#include "brdf.glsl"
layout(constant_id = 1) const int LTC_LINE_NODES = 8;  // the tube_nodes parameter
#include "ltc.glsl"
#include "../shadow/local_moments.glsl"
#include "../shadow/local_layout.glsl.h"
#include "tiled.glsl.h"
// shadow.local_data's counts.y: 4, moment shadow maps; 2, variance shadow maps. A constant:
// lavapipe would run both reconstructions for every spot light otherwise.
layout(constant_id = 2) const int LOCAL_MOMENTS = 4;

layout(local_size_x = kLightingTile, local_size_y = kLightingTile) in;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std430, set = 0, binding = NC_BINDING(frame_lights)) readonly buffer LightBlock { GpuLight lights[]; };
layout(set = 0, binding = NC_BINDING(gbuffer_albedo)) uniform sampler2D albedo_map;
layout(set = 0, binding = NC_BINDING(gbuffer_normal)) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(gbuffer_material)) uniform sampler2D material_map;
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
layout(set = 0, binding = NC_BINDING(depth_linear)) uniform sampler2D linear_depth_map;
layout(set = 0, binding = NC_BINDING(lights_clusters)) uniform usampler3D clusters;
layout(std430, set = 0, binding = NC_BINDING(lights_cluster_indices)) readonly buffer IndexBlock { uint cluster_indices[]; };
// lights.cluster_stats, for the froxels' shape. All zero when lights.cluster was skipped (no
// local light), every list then empty: the max(…, 1) below keep the arithmetic defined there.
layout(std430, set = 0, binding = NC_BINDING(lights_cluster_stats)) readonly buffer ClusterStatsBlock { GpuClusterStats cluster_stats; };
layout(set = 0, binding = NC_BINDING(lighting_ltc_inverse)) uniform sampler2D ltc_inverse;
layout(set = 0, binding = NC_BINDING(lighting_ltc_magnitude)) uniform sampler2D ltc_magnitude;
layout(set = 0, binding = NC_BINDING(shadow_sun)) uniform sampler2D sun_shadow_map;
// shadow.local_plan's maps (passes/shadow/local_layout.h), each light's map or -1, the moments.
layout(std140, set = 0, binding = NC_BINDING(shadow_local_data)) uniform LocalShadowBlock { GpuLocalShadows local_shadows; };
layout(std430, set = 0, binding = NC_BINDING(shadow_local_slots)) readonly buffer LocalSlotBlock { int local_slots[]; };
layout(set = 0, binding = NC_BINDING(shadow_local_moments)) uniform sampler2DArray local_moments;
layout(set = 0, binding = NC_BINDING(lighting_diffuse), rgba16f) uniform writeonly image2D diffuse_out;
layout(set = 0, binding = NC_BINDING(lighting_specular), rgba16f) uniform writeonly image2D specular_out;
layout(std430, set = 0, binding = NC_BINDING(lighting_tile_classes)) buffer ClassBlock { GpuTileClasses classes; };
layout(std430, set = 0, binding = NC_BINDING(lighting_tile_lists)) buffer ListBlock { GpuTileEntry entries[]; };

layout(constant_id = 0) const uint phase = 0u;  // one pipeline per phase (tiled.cpp says why)

layout(push_constant) uniform TiledConstants { NC_BLOCK_MEMBERS(NC_TILED_CONSTANTS_FIELDS) };

bool inside(ivec2 pixel) { return all(lessThan(pixel, ivec2(camera.viewport.xy))); }

// Sky, or unlit (lighting.composite adds emission): nothing to shade.
bool shaded(ivec2 pixel) {
  return texelFetch(depth_map, pixel, 0).r > 0.0 && texelFetch(albedo_map, pixel, 0).a == 0.0;
}

// The slice of lights.clusters a linear depth falls in: passes/lights/cluster_layout.h's formula,
// then moved so that it lies between the slice's bounds as cluster.comp computes them (the same
// float expressions), which float rounding of the logarithm could otherwise miss by one.
uint pixel_slice(float depth) {
  int slices = int(max(cluster_stats.slices, 1u));
  float znear = camera.projection_params.x;
  float far = max(cluster_stats.max_distance, 2.0 * znear);
  float step = log2(far / znear) / float(slices);
  int k = clamp(int(floor(log2(depth / znear) / step)), 0, slices - 1);
  if (k < slices - 1 && depth >= znear * exp2(float(k + 1) * step)) ++k;
  if (k > 0 && depth < znear * exp2(float(k) * step)) --k;
  return uint(k);
}

// The froxel list of a pixel at a linear depth: (offset, count) into cluster_indices.
uvec2 froxel_list(ivec2 pixel, float depth) {
  uvec2 tile = uvec2(pixel) / max(cluster_stats.tile_size, 1u);
  return texelFetch(clusters, ivec3(tile, pixel_slice(depth)), 0).xy;
}

// Phase 0.
shared uint tile_flags;  // 1: a lit pixel; 2: its froxel lists a local light; 4: a tube; 8: a sphere

void classify() {
  uvec2 tile = gl_WorkGroupID.xy;
  ivec2 pixel = ivec2(tile * kLightingTile + gl_LocalInvocationID.xy);
  if (gl_LocalInvocationIndex == 0u) tile_flags = 0u;
  barrier();
  if (inside(pixel) && shaded(pixel)) {
    uvec2 list = froxel_list(pixel, texelFetch(linear_depth_map, pixel, 0).r);
    // The list ascends: point and spot lights, then spheres, then tubes.
    uint flags = list.y > 0u ? 3u : 1u;
    for (uint k = 0u; k < list.y; ++k) {
      uint i = cluster_indices[list.x + k];
      if (i >= frame.light_groups.z) flags |= 4u;
      else if (i >= frame.light_groups.y) flags |= 8u;
    }
    atomicOr(tile_flags, flags);
  }
  barrier();
  uint tile_class = (tile_flags & 12u) == 12u ? 5u
                    : (tile_flags & 8u) != 0u ? 4u
                    : (tile_flags & 4u) != 0u ? 3u
                    : (tile_flags & 2u) != 0u ? 2u
                    : tile_flags;
  if (tile_class == 0u && inside(pixel)) {
    imageStore(diffuse_out, pixel, vec4(0.0));
    imageStore(specular_out, pixel, vec4(0.0));
  }
  uint groups = tiles_x * tiles_y;
  uint group = tile.y * tiles_x + tile.x;
  if (gl_LocalInvocationIndex == 0u) entries[group] = GpuTileEntry(tile_class, 0u);
  for (uint i = groups + group * kLightingTileInvocations + gl_LocalInvocationIndex; i < entries.length(); i += groups * kLightingTileInvocations)
    entries[i] = GpuTileEntry(0u, 0u);
}

// Phase 1.
shared uint run_counts[kLightingTileClasses][kLightingTileInvocations];  // tiles of classes 1 to 5 in each invocation's run

void place() {
  uint lane = gl_LocalInvocationIndex;
  uint total = tiles_x * tiles_y;
  uint per_run = (total + kLightingTileInvocations - 1u) / kLightingTileInvocations;
  uint begin = min(lane * per_run, total), end = min(begin + per_run, total);
  uint counts[kLightingTileClasses] = uint[kLightingTileClasses](0u, 0u, 0u, 0u, 0u);
  for (uint t = begin; t < end; ++t) {
    uint tile_class = entries[t].tile_class;
    if (tile_class > 0u) ++counts[tile_class - 1u];
  }
  for (uint c = 0u; c < kLightingTileClasses; ++c) run_counts[c][lane] = counts[c];
  barrier();
  // Each class's list follows the previous classes' lists.
  uint at[kLightingTileClasses], first[kLightingTileClasses], all[kLightingTileClasses];
  uint listed = 0u;
  for (uint c = 0u; c < kLightingTileClasses; ++c) {
    uint before = 0u;
    all[c] = 0u;
    for (uint k = 0u; k < kLightingTileInvocations; ++k) {
      if (k < lane) before += run_counts[c][k];
      all[c] += run_counts[c][k];
    }
    first[c] = listed;
    at[c] = listed + before;
    listed += all[c];
  }
  for (uint t = begin; t < end; ++t) {
    uint tile_class = entries[t].tile_class;
    if (tile_class > 0u) entries[at[tile_class - 1u]++].listed_tile = t;
  }
  if (lane != 0u) return;
  // A class with no tile dispatches nothing; (0, 0, 0) is also the buffer's cleared value, which
  // a frame with nothing to shade then computes (the pass's skip for cleared inputs).
  uvec4 dispatch[kLightingTileClasses];
  for (uint c = 0u; c < kLightingTileClasses; ++c) {
    uint any = min(all[c], 1u);
    dispatch[c] = uvec4(all[c], any, any, first[c]);
  }
  classes = GpuTileClasses(dispatch[0], dispatch[1], dispatch[2], dispatch[3], dispatch[4]);
}

// Phases 2 to 6.

// Lambert's illuminance from a sphere of unit radiance whose centre is at cosine `cos_theta` to
// the normal and whose angular radius σ has sin²σ = `sin2_sigma`, the part below the horizon
// cut away (Snyder 1996, in the form of Lagarde and de Rousiers 2014).
float sphere_illuminance(float cos_theta, float sin2_sigma) {
  if (sin2_sigma >= 1.0) return PI;  // inside it: light from the whole hemisphere
  if (cos_theta * cos_theta > sin2_sigma) return PI * sin2_sigma * max(cos_theta, 0.0);
  float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
  float x = sqrt(1.0 / sin2_sigma - 1.0);
  float y = -x * cos_theta / sin_theta;
  float sin_theta_y = sin_theta * sqrt(max(1.0 - y * y, 0.0));
  float e = (cos_theta * acos(clamp(y, -1.0, 1.0)) - x * sin_theta_y) * sin2_sigma + atan(sin_theta_y, x);
  return max(e, 0.0);
}

struct Surface {
  vec3 position, n, v, albedo, f0;
  float metallic, roughness, alpha;
};

// The surface's LTC lobe: its frame, the view in it, M⁻¹ and the magnitudes (norm, fresnel).
struct Lobe {
  mat3 frame;
  vec3 v;
  vec4 minv;
  vec2 magnitude;
};

Lobe lobe_of(Surface s) {
  Lobe lobe;
  lobe.frame = ltc_frame(s.n, s.v);
  lobe.v = lobe.frame * s.v;
  ltc_lookup(ltc_inverse, ltc_magnitude, s.roughness, clamp(dot(s.n, s.v), 0.0, 1.0), lobe.minv, lobe.magnitude);
  return lobe;
}

// Variance shadow maps: Chebyshev's upper bound P(t ≤ depth) = σ² / (σ² + (t − μ)²) on the
// fraction of the filter lit, from the filtered moments (μ, E[t²]) in .rg.
float chebyshev_visibility(vec4 m, float t) {
  if (t <= m.x) return 1.0;
  float variance = max(m.y - m.x * m.x, local_min_variance);
  float d = t - m.x;
  return variance / (variance + d * d);
}

// Moment shadow maps (Peters and Klein 2015, algorithm 3, Hamburger 4MSM): the moments b, mixed
// with those of t = ½ by local_moment_bias, are those of some distribution of depths; of all
// such, the one that puts the least weight in front of the receiver (depth z) has three points,
// z and the roots z₂ ≤ z₃ of the polynomial c₁ + c₂x + c₃x² whose coefficients solve
// B c = (1, z, z²) for the Hankel matrix B = (b_{i+j}), i, j = 0…2 (b₀ = 1; Cholesky, B = L D Lᵀ).
// Its weight in front, the shadow: 0 if z ≤ z₂; z₂'s weight if z ≤ z₃; else all but z's.
float moment_visibility(vec4 q, float z) {
  vec4 b = mix(decode_moments(q), vec4(0.5), local_moment_bias);
  float d22 = b.y - b.x * b.x;
  float l32 = (b.z - b.x * b.y) / d22;
  float d33 = b.w - b.y * b.y - l32 * l32 * d22;
  float y2 = z - b.x;
  float y3 = z * z - b.y - l32 * y2;
  float c3 = y3 / d33;
  float c2 = y2 / d22 - l32 * c3;
  float c1 = 1.0 - b.x * c2 - b.y * c3;
  float p = c2 / c3, r = sqrt(max(0.25 * p * p - c1 / c3, 0.0));
  float z2 = -0.5 * p - r, z3 = -0.5 * p + r;
  float shadow;
  if (z <= z2)
    shadow = 0.0;
  else if (z <= z3)
    shadow = (z * z3 - b.x * (z + z3) + b.y) / ((z3 - z2) * (z - z2));
  else
    shadow = 1.0 - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((z - z2) * (z - z3));
  return 1.0 - clamp(shadow, 0.0, 1.0);
}

// How much of light `index`'s light reaches `position`: 1 without a map, or outside its map's
// frustum; else the moments' visibility (LOCAL_MOMENTS) at the receiver's linear depth less
// local_bias, with the part below local_bleeding cut away and the rest rescaled (light-bleeding
// reduction: where two occluders overlap, a bound stays above 0 behind both).
float local_visibility(uint index, vec3 position) {
  int slot = local_slots[index];
  if (slot < 0) return 1.0;
  vec4 at = vec4(position, 1.0);
  vec4 clip = vec4(dot(local_shadows.clip_x[slot], at), dot(local_shadows.clip_y[slot], at),
                   dot(local_shadows.clip_z[slot], at), dot(local_shadows.clip_w[slot], at));
  vec4 range = local_shadows.depth_range[slot];
  if (clip.w <= range.x) return 1.0;
  vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  float t = (clip.w - range.x) * range.z - local_bias;
  vec4 m = textureLod(local_moments, vec3(uv, float(slot)), 0.0);
  float p = LOCAL_MOMENTS == 4 ? moment_visibility(m, t) : chebyshev_visibility(m, t);
  return clamp((p - local_bleeding) / (1.0 - local_bleeding), 0.0, 1.0);
}

// Each kind of light has its own function and its own loop in shade_tiles(): lavapipe runs both
// sides of a branch, so shading kinds apart keeps a point light from paying for a tube's LTC.
void shade_punctual(uint index, Surface s, inout vec3 diffuse, inout vec3 specular) {
  GpuLight light = lights[index];
  vec3 radiance = light.color_range.rgb * intensity_scale;
  float range = light.color_range.w;
  vec3 to_light = light.position_type.xyz - s.position;
  float d2 = max(dot(to_light, to_light), 1e-8);
  if (range > 0.0 && d2 >= range * range) return;
  float d = sqrt(d2);
  vec3 l = to_light / d;
  float attenuation = range_window(d, range) / d2;
  if (uint(light.position_type.w) == kLightSpot)
    attenuation *= spot_cone(light.direction_cos_outer.xyz, light.direction_cos_outer.w, light.cos_inner.x, l) *
                   local_visibility(index, s.position);
  if (attenuation <= 0.0) return;
  diffuse += diffuse_term(s.n, l, radiance * attenuation, s.albedo, s.metallic);
  specular += specular_term(s.n, s.v, l, radiance * attenuation, s.albedo, s.metallic, s.alpha);
}

// A sphere of `radiance` candela seen from any side: radiance / (π r²) per unit area.
void shade_sphere(GpuLight light, Surface s, Lobe lobe, inout vec3 diffuse, inout vec3 specular) {
  float range = light.color_range.w, radius = light.end_radius.w;
  vec3 to_light = light.position_type.xyz - s.position;
  float d2 = max(dot(to_light, to_light), 1e-8);
  if (range > 0.0 && d2 >= range * range) return;
  float d = sqrt(d2);
  float window = range_window(d, range);
  if (window <= 0.0) return;
  vec3 unit = light.color_range.rgb * intensity_scale * (window / (PI * radius * radius));
  float e = sphere_illuminance(dot(s.n, to_light / d), min(radius * radius / d2, 1.0));
  diffuse += s.albedo * (1.0 - s.metallic) * (1.0 / PI) * e * unit;
  vec2 lit = ltc_sphere(lobe.minv, lobe.magnitude, lobe.v, lobe.frame * to_light, radius);
  specular += (s.f0 * lit.x + (1.0 - s.f0) * lit.y) * unit;
}

// A line light of `radiance` candela per metre.
void shade_tube(GpuLight light, Surface s, Lobe lobe, inout vec3 diffuse, inout vec3 specular) {
  vec3 radiance = light.color_range.rgb * intensity_scale;
  float range = light.color_range.w;
  vec3 a = light.position_type.xyz - s.position, b = light.end_radius.xyz - s.position;
  vec3 ab = b - a;
  vec3 nearest = a + ab * clamp(-dot(a, ab) / max(dot(ab, ab), 1e-8), 0.0, 1.0);
  if (range > 0.0 && dot(nearest, nearest) >= range * range) return;
  vec3 t = ltc_tube(lobe.minv, lobe.magnitude.x, lobe.v, lobe.frame * a, lobe.frame * b, light.end_radius.w, range);
  diffuse += s.albedo * (1.0 - s.metallic) * radiance * t.z;
  specular += (s.f0 * t.x + (1.0 - s.f0) * t.y) * radiance;
}

// Contact shadow toward a directional light `l` (unit, toward the light): a march of
// contact_steps steps over contact_length metres from the surface in screen space; the point is
// occluded where depth.linear there lies in front of the ray by more than a bias (a step's
// share of the ray plus 0.1% of the depth, against self-shadowing) and less than
// contact_thickness (what is farther in front is taken to be a separate object the ray passes
// behind). 0: occluded; 1: not, or the ray leaves the view first.
float contact_shadow(vec3 position, vec3 l) {
  float step_length = contact_length / float(max(contact_steps, 1u));
  for (uint i = 1u; i <= contact_steps; ++i) {
    vec4 clip = camera.view_projection * vec4(position + l * (step_length * float(i)), 1.0);
    if (clip.w <= 0.0) break;  // behind the camera
    vec2 screen = (clip.xy / clip.w * 0.5 + 0.5) * camera.viewport.xy;
    if (any(lessThan(screen, vec2(0.0))) || any(greaterThanEqual(screen, camera.viewport.xy))) break;
    float in_front = clip.w - texelFetch(linear_depth_map, ivec2(screen), 0).r;
    if (in_front > 0.5 * step_length + 1e-3 * clip.w && in_front < contact_thickness) return 0.0;
  }
  return 1.0;
}

// The first entry of class `tile_class`'s list in lighting.tile_lists.
uint first_listed(uint tile_class) {
  switch (tile_class) {
    case 1u: return classes.directional.w;
    case 2u: return classes.local.w;
    case 3u: return classes.tube.w;
    case 4u: return classes.sphere.w;
  }
  return classes.sphere_and_tube.w;
}

void shade_tiles(uint tile_class) {
  uint tile_index = entries[first_listed(tile_class) + gl_WorkGroupID.x].listed_tile;
  uvec2 tile = uvec2(tile_index % tiles_x, tile_index / tiles_x);
  ivec2 pixel = ivec2(tile * kLightingTile + gl_LocalInvocationID.xy);
  if (!inside(pixel)) return;
  float depth = texelFetch(depth_map, pixel, 0).r;
  vec4 albedo_flags = texelFetch(albedo_map, pixel, 0);
  if (depth <= 0.0 || albedo_flags.a > 0.0) {
    imageStore(diffuse_out, pixel, vec4(0.0));
    imageStore(specular_out, pixel, vec4(0.0));
    return;
  }

  vec2 ndc = (vec2(pixel) + 0.5) * camera.viewport.zw * 2.0 - 1.0;
  vec4 p = camera.inverse_view_projection * vec4(ndc, depth, 1.0);
  Surface s;
  s.position = p.xyz / p.w;  // camera-relative world
  s.v = normalize(camera.eye.xyz - s.position);
  s.n = normalize(texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0);
  vec4 material = texelFetch(material_map, pixel, 0);
  s.albedo = albedo_flags.rgb;
  s.metallic = material.r;
  s.roughness = max(material.g, min_roughness);
  s.alpha = s.roughness * s.roughness;
  s.f0 = mix(vec3(0.04), s.albedo, s.metallic);

  vec3 diffuse = vec3(0.0), specular = vec3(0.0);
  if (frame.sun_direction.w > 0.0) {
    float sun_visibility = texelFetch(sun_shadow_map, pixel, 0).r;
    vec3 e = frame.sun_radiance.rgb * intensity_scale * sun_visibility * contact_shadow(s.position, -frame.sun_direction.xyz);
    diffuse += diffuse_term(s.n, -frame.sun_direction.xyz, e, s.albedo, s.metallic);
    specular += specular_term(s.n, s.v, -frame.sun_direction.xyz, e, s.albedo, s.metallic, s.alpha);
  }
  // Directional lights besides the sun are not clustered: they open frame.lights.
  for (uint i = 0u; i < frame.light_groups.x; ++i) {
    vec3 radiance = lights[i].color_range.rgb * intensity_scale;
    vec3 l = -lights[i].direction_cos_outer.xyz;
    diffuse += diffuse_term(s.n, l, radiance, s.albedo, s.metallic);
    specular += specular_term(s.n, s.v, l, radiance, s.albedo, s.metallic, s.alpha);
  }
  if (tile_class >= 2u) {
    uvec2 list = froxel_list(pixel, texelFetch(linear_depth_map, pixel, 0).r);
    // A list ascends, so it holds its point and spot lights, then its spheres, then its tubes.
    uint k = 0u;
    for (; k < list.y; ++k) {
      uint i = cluster_indices[list.x + k];
      if (i >= frame.light_groups.y) break;
      shade_punctual(i, s, diffuse, specular);
    }
    // Only classes 4 and 5 have spheres, 3 and 5 tubes: lavapipe runs a loop's body at least
    // once per SIMD row, even where no list holds a light of its kind (tiled_layout.h).
    if (tile_class >= 3u) {
      Lobe lobe = lobe_of(s);
      if (tile_class >= 4u) {
        for (; k < list.y; ++k) {
          uint i = cluster_indices[list.x + k];
          if (i >= frame.light_groups.z) break;
          shade_sphere(lights[i], s, lobe, diffuse, specular);
        }
      }
      if (tile_class != 4u)
        for (; k < list.y; ++k) shade_tube(lights[cluster_indices[list.x + k]], s, lobe, diffuse, specular);
    }
  }
  imageStore(diffuse_out, pixel, vec4(nearest_half(diffuse), 1.0));
  imageStore(specular_out, pixel, vec4(nearest_half(specular), 1.0));
}

void main() {
  if (phase == 0u)
    classify();
  else if (phase == 1u)
    place();
  else
    shade_tiles(phase - 1u);
}
