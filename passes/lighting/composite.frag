#version 460
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "composite.glsl.h"

layout(set = 0, binding = NC_BINDING(lighting_diffuse)) uniform sampler2D diffuse_map;
layout(set = 0, binding = NC_BINDING(lighting_specular)) uniform sampler2D specular_map;
layout(set = 0, binding = NC_BINDING(gbuffer_albedo)) uniform sampler2D albedo_map;
layout(set = 0, binding = NC_BINDING(gbuffer_normal)) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(gbuffer_material)) uniform sampler2D material_map;
layout(set = 0, binding = NC_BINDING(gbuffer_emissive)) uniform sampler2D emissive_map;
layout(set = 0, binding = NC_BINDING(gbuffer_occlusion)) uniform sampler2D occlusion_map;
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
#ifdef NC_BINDING_ao
layout(set = 0, binding = NC_BINDING(ao)) uniform sampler2D ao_map;  // ao.bent; alpha: the visibility
#endif

#if defined(NC_BINDING_sky_view) && defined(NC_BINDING_sky_atmosphere) && defined(NC_BINDING_frame_constants) && \
    defined(NC_BINDING_frame_views)
#define NC_SKY_VIEW
#include "../sky/atmosphere.glsl.h"
layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_view)) uniform sampler2D sky_view_lut;
#ifdef NC_BINDING_sky_aerial_perspective
#define NC_AERIAL_PERSPECTIVE
layout(set = 0, binding = NC_BINDING(sky_aerial_perspective)) uniform sampler3D aerial_volume;
#endif
#endif

#if defined(NC_SKY_VIEW) && defined(NC_BINDING_sky_irradiance) && defined(NC_BINDING_sky_specular) && \
    defined(NC_BINDING_lighting_dfg)
#define NC_IMAGE_BASED
#include "../sky/ibl.glsl.h"
layout(std430, set = 0, binding = NC_BINDING(sky_irradiance)) readonly buffer IrradianceBlock {
  GpuSkyIrradiance irradiance;
};
layout(set = 0, binding = NC_BINDING(sky_specular)) uniform samplerCube specular_cube;
layout(set = 0, binding = NC_BINDING(lighting_dfg)) uniform sampler2D dfg_lut;
#endif

#if defined(NC_IMAGE_BASED) && defined(NC_BINDING_probes_slots) && defined(NC_BINDING_probes_array)
#define NC_PROBES
#define NC_PROBE_SLOTS
#include "../probes/capture_layout.glsl.h"
#include "../probes/paraboloid.glsl.h"
layout(std430, set = 0, binding = NC_BINDING(probes_slots)) readonly buffer ProbeSlotBlock { GpuProbeSlot slots[]; };
layout(set = 0, binding = NC_BINDING(probes_array)) uniform sampler2DArray probe_array;
#include "../probes/reflection.glsl"
#endif

#if defined(NC_IMAGE_BASED) && defined(NC_BINDING_shadow_topdown) && defined(NC_BINDING_shadow_topdown_data)
#define NC_TOPDOWN
#include "../shadow/topdown_layout.glsl.h"
layout(std140, set = 0, binding = NC_BINDING(shadow_topdown_data)) uniform TopdownBlock { GpuTopdown topdown; };
layout(set = 0, binding = NC_BINDING(shadow_topdown)) uniform sampler2D topdown_map;
#include "../shadow/topdown.glsl"
#endif

#if defined(NC_IMAGE_BASED) && defined(NC_BINDING_gi_volume) && defined(NC_BINDING_gi_volume_data)
#define NC_GI_VOLUME
#include "../gi/volume_layout.glsl.h"
layout(std140, set = 0, binding = NC_BINDING(gi_volume_data)) uniform GiVolumeBlock { GpuGiVolume gi; };
layout(set = 0, binding = NC_BINDING(gi_volume)) uniform sampler3D gi_cells;
#endif

layout(push_constant) uniform CompositeConstants { NC_BLOCK_MEMBERS(NC_COMPOSITE_CONSTANTS_FIELDS) };

#ifdef NC_SKY_VIEW
#include "../sky/atmosphere.glsl"
#include "../sky/camera_height.glsl"
#include "../sky/view_lookup.glsl"

// The view ray through a pixel, camera-relative.
vec3 view_ray(vec2 pixel_centre) {
  vec2 ndc = pixel_centre * camera.viewport.zw * 2.0 - 1.0;
  vec4 near_point = camera.inverse_view_projection * vec4(ndc, 1.0, 1.0);
  return normalize(near_point.xyz / near_point.w - camera.eye.xyz);
}

// The camera-relative position drawn at `pixel`, from its depth.
vec3 position_at(ivec2 pixel, float depth) {
  vec2 ndc = (vec2(pixel) + 0.5) * camera.viewport.zw * 2.0 - 1.0;
  vec4 p = camera.inverse_view_projection * vec4(ndc, depth, 1.0);
  return p.xyz / p.w;
}
#endif

#ifdef NC_AERIAL_PERSPECTIVE
// The surface's radiance as it reaches the camera through the air (sky.aerial_perspective):
// dimmed by the air's transmittance, with the light the air scatters toward the camera added.
// Slice k of N ends at kSkyAerialDistanceKm ((k + 1) / N)² km, so a point at distance d lies at
// slice coordinate N sqrt(d / kSkyAerialDistanceKm) - 1 (nearer than the first slice's end: the
// first slice); the volume holds each figure per km of its slice's length.
vec3 through_air(vec3 radiance, vec3 position) {
  float slices = float(textureSize(aerial_volume, 0).z);
  float distance_km = length(position - camera.eye.xyz) * 1e-3;
  float slice = slices * sqrt(distance_km / kSkyAerialDistanceKm) - 1.0;
  vec3 uvw = vec3(gl_FragCoord.xy * camera.viewport.zw, (max(slice, 0.0) + 0.5) / slices);
  vec4 air = textureLod(aerial_volume, uvw, 0.0);
  return radiance * exp(-air.a * distance_km) + air.rgb * distance_km;
}
#endif

#ifdef NC_IMAGE_BASED
#include "../sky/sh.glsl"
#include "environment_light.glsl"
#include "../ao/specular_occlusion.glsl"
#ifdef NC_GI_VOLUME
#include "../gi/volume_lookup.glsl"
#endif

// The surface's own orientation (not the normal map's) from the depth of the neighbours: along
// each axis the side whose depth is nearer this pixel's, so that an edge does not bend it.
vec3 geometric_normal(ivec2 pixel, float depth, vec3 position) {
  ivec2 last = textureSize(depth_map, 0) - 1;
  vec3 axis[2];
  for (int a = 0; a < 2; ++a) {
    ivec2 step_to = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
    ivec2 after = min(pixel + step_to, last), before = max(pixel - step_to, ivec2(0));
    float depth_after = texelFetch(depth_map, after, 0).r, depth_before = texelFetch(depth_map, before, 0).r;
    bool use_after = abs(depth_after - depth) <= abs(depth_before - depth) && depth_after > 0.0;
    if (!use_after && depth_before <= 0.0) return vec3(0.0);
    axis[a] = use_after ? position_at(after, depth_after) - position : position - position_at(before, depth_before);
  }
  vec3 n = cross(axis[1], axis[0]);
  return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
}

// The sky's light reflected toward the camera at `pixel` (environment_light()), with the
// surface's geometric normal from the depth of its neighbours.
Indirect image_based(ivec2 pixel, float depth, vec3 position, vec3 albedo, float metallic, float roughness,
                     float visibility, vec4 ao) {
  vec3 v = normalize(camera.eye.xyz - position);
  vec3 n = normalize(texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0);
  vec3 r = dominant_direction(n, v, roughness);
  vec3 prefiltered = textureLod(specular_cube, r, roughness * float(kSkySpecularMips - 1u)).rgb;
#ifdef NC_PROBES
  // The two nearest probes whose boxes hold the point, each read along its parallax-corrected
  // direction and weighted by how deep inside its box the point lies; the sky makes up what their
  // weights leave. probes.slots lists the slots holding a capture.
  NearestProbes nearest = nearest_probes(position, uint(probes.y), probes.x);
  vec3 probe_sum = vec3(0.0);
  float total = 0.0;
  for (int i = 0; i < 2; ++i) {
    if (nearest.weight[i] <= 0.0) continue;
    GpuProbeSlot slot = slots[nearest.index[i]];
    vec3 d = parallax_direction(position, r, slot.box_min.xyz, slot.box_max.xyz, slot.position.xyz);
    probe_sum += nearest.weight[i] * probe_radiance(uint(slot.position.w), d, roughness * float(kProbeArrayMips - 1u));
    total += nearest.weight[i];
  }
  prefiltered = total > 1.0 ? probe_sum / total : probe_sum + (1.0 - total) * prefiltered;
#endif
  // Indirect diffuse: the GI volume's where it holds the point, the sky's irradiance where the
  // sky is straight above it elsewhere (and across the volume's outer half cell, the two mixed).
  vec3 irradiance_n = irradiance_over_pi(n);
#ifdef NC_TOPDOWN
  irradiance_n *= topdown_sky_visibility(position, n);
#endif
#ifdef NC_GI_VOLUME
  if (sky_source.z != 0u) {
    // Read half a cell off the surface along its normal: a floor midway between the cells above
    // and below it would otherwise take half its light from the cell under the ground.
    vec3 gathered;
    float inside = gi_volume_irradiance(position + n * (0.5 * gi.origin.w), n, gathered);
    irradiance_n = mix(irradiance_n, gathered, inside);
  }
#endif
  float ao_specular = cone_specular_occlusion(ao.xyz, ao.a, r, roughness);
  return environment_light(n, v, r, geometric_normal(pixel, depth, position), albedo, metallic, roughness, visibility,
                           ao.a, ao_specular, sky_source.y != 0u, prefiltered, irradiance_n);
}
#endif

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_lit;
layout(location = 1) out vec4 out_specular;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 lit = sky.rgb, specular = vec3(0.0);
  float depth = texelFetch(depth_map, pixel, 0).r;
  vec4 albedo = texelFetch(albedo_map, pixel, 0);
  vec3 emitted = texelFetch(emissive_map, pixel, 0).rgb;
#ifdef NC_SKY_VIEW
  // The camera-relative point drawn here, which the image-based light and the air both start from.
  vec3 position = depth > 0.0 ? position_at(pixel, depth) : vec3(0.0);
#endif
  if (depth <= 0.0) {
#ifdef NC_SKY_VIEW
    if (sky_source.x != 0u) lit = sky_view_radiance(view_ray(gl_FragCoord.xy));
#endif
  } else if (albedo.a > 0.0) {
    lit = albedo.rgb + emitted;  // unlit: the base colour is the result
  } else {
    vec4 material = texelFetch(material_map, pixel, 0);
    float metallic = material.r;
    // The material's occlusion and the frame's AO both say how much indirect light arrives. ao:
    // the bent normal (the zero vector: no cone) and the visibility.
    float visibility = texelFetch(occlusion_map, pixel, 0).r;
    vec4 ao = vec4(0.0, 0.0, 0.0, 1.0);
#ifdef NC_BINDING_ao
    ao = textureLod(ao_map, in_uv, 0.0);
    ao.xyz = ao.xyz * 2.0 - 1.0;
#endif
    specular = texelFetch(specular_map, pixel, 0).rgb;
    vec3 indirect_diffuse = ambient.rgb * albedo.rgb * (1.0 - metallic) * (visibility * ao.a);
#ifdef NC_IMAGE_BASED
    if (sky_source.x != 0u) {
      Indirect sky_light = image_based(pixel, depth, position, albedo.rgb, metallic, material.g, visibility, ao);
      indirect_diffuse += sky_light.diffuse;
      specular += sky_light.specular;
    }
#endif
    lit = texelFetch(diffuse_map, pixel, 0).rgb + specular + emitted + indirect_diffuse;
  }
#ifdef NC_AERIAL_PERSPECTIVE
  if (depth > 0.0 && sky_source.x != 0u) lit = through_air(lit, position);
#endif
  out_lit = vec4(nearest_half(lit), 1.0);
  out_specular = vec4(nearest_half(specular), 1.0);
}
