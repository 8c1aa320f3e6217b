#version 460
// probes.light: the lit colour of each texel of this frame's captured faces, as the frame's own
// passes would light it from the face's view (lighting.deferred's direct light, then
// lighting.composite's sum) with these differences: the sun's shadow comes from shadow.distant's
// levels alone (the cascades cover the camera's frustum, not the probe's surroundings), the local
// lights are the capture's own (probes.lights, unshadowed), there is no horizon occlusion and no
// aerial perspective. Where nothing was drawn: the sky along the texel's direction, from
// sky.cubemap's first level (sky.view's radiance at 128 texels a face; the composite reads
// sky.view itself: in this shader lavapipe crashed reading it). One level
// per dispatch: level 0 lit, each later one the mean of the 2×2 texels above it on the same face
// (the chain probes.convert's prefilter picks its levels from).
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "../lighting/brdf.glsl"
#include "../lighting/direct_light.glsl"
#include "../shadow/shadow_layout.glsl.h"
#include "../shadow/sun_filter.glsl"
#include "../sky/ibl.glsl.h"
#include "../shadow/topdown_layout.glsl.h"
#include "capture_layout.glsl.h"
#include "light.glsl.h"

layout(local_size_x = kProbeLightGroupSide, local_size_y = kProbeLightGroupSide) in;
// 1 when sky.atmosphere holds a record (the sky's passes ran): the sky's light and cube map. A
// specialization constant, so a frame without the sky reads none of its (empty) resources:
// lavapipe runs both sides of a branch.
layout(constant_id = 0) const uint HAS_SKY = 1u;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
#include "../frame/views.glsl"
layout(std430, set = 0, binding = NC_BINDING(probes_face_draws)) readonly buffer FaceBlock { GpuProbeFace faces[]; };
layout(std430, set = 0, binding = NC_BINDING(probes_lights)) readonly buffer LightBlock { GpuLight lights[]; };
layout(set = 0, binding = NC_BINDING(probes_gbuffer_albedo)) uniform sampler2DArray albedo_map;
layout(set = 0, binding = NC_BINDING(probes_gbuffer_normal)) uniform sampler2DArray normal_map;
layout(set = 0, binding = NC_BINDING(probes_gbuffer_material)) uniform sampler2DArray material_map;
layout(set = 0, binding = NC_BINDING(probes_gbuffer_emissive)) uniform sampler2DArray emissive_map;
layout(set = 0, binding = NC_BINDING(probes_gbuffer_occlusion)) uniform sampler2DArray occlusion_map;
layout(set = 0, binding = NC_BINDING(probes_depth)) uniform sampler2DArray depth_map;
layout(std140, set = 0, binding = NC_BINDING(shadow_distant_data)) uniform DistantBlock { GpuDistantLevels distant; };
layout(set = 0, binding = NC_BINDING(shadow_distant)) uniform sampler2DArray distant_maps;
layout(set = 0, binding = NC_BINDING(sky_cubemap)) uniform samplerCube sky_cube;
layout(std430, set = 0, binding = NC_BINDING(sky_irradiance)) readonly buffer IrradianceBlock {
  GpuSkyIrradiance irradiance;
};
layout(set = 0, binding = NC_BINDING(sky_specular)) uniform samplerCube specular_cube;
layout(set = 0, binding = NC_BINDING(lighting_dfg)) uniform sampler2D dfg_lut;
layout(set = 0, binding = NC_BINDING(probes_faces), rgba16f) uniform readonly imageCubeArray level_above;
layout(set = 0, binding = NC_BINDING(probes_faces) + 1, rgba16f) uniform writeonly imageCubeArray faces_out;

layout(push_constant) uniform ProbeLightConstants { NC_BLOCK_MEMBERS(NC_PROBE_LIGHT_CONSTANTS_FIELDS) };

layout(std140, set = 0, binding = NC_BINDING(shadow_topdown_data)) uniform TopdownBlock { GpuTopdown topdown; };
layout(set = 0, binding = NC_BINDING(shadow_topdown)) uniform sampler2D topdown_map;
#include "../shadow/topdown.glsl"
#include "../sky/sh.glsl"
#include "../lighting/environment_light.glsl"

// The sun's visibility at a face's point from the finest distant level that holds the filter's
// texels around it (none: lit).
float sun_visibility(vec3 position, vec3 n) {
  int level = distant_level(distant, position, filter_radius);
  if (level >= int(kDistantLevels)) return 1.0;
  float resolution = distant.light_direction.w;
  ShadowMap map = ShadowMap(level, distant.light_from_world[level], distant.texel_metres[level],
                            distant.depth_metres[level], resolution);
  Receiver r = receiver_in(map, position, n, max_slope, depth_bias);
  int side = 2 * filter_radius + 1;
  return lit_taps(distant_maps, map.layer, r, filter_radius, int(resolution) - 1, side * side) / float(side * side);
}

void main() {
  ivec3 texel = ivec3(gl_GlobalInvocationID);
  ivec2 size = imageSize(faces_out).xy;
  if (texel.z >= faces.length() || any(greaterThanEqual(texel.xy, size))) return;
  if (level > 0u) {
    ivec3 first = ivec3(texel.xy * 2, texel.z);
    vec3 mean = 0.25 * (imageLoad(level_above, first).rgb + imageLoad(level_above, first + ivec3(1, 0, 0)).rgb +
                        imageLoad(level_above, first + ivec3(0, 1, 0)).rgb +
                        imageLoad(level_above, first + ivec3(1, 1, 0)).rgb);
    imageStore(faces_out, texel, vec4(nearest_half(mean), 1.0));
    return;
  }
  GpuView view = views[texel.z];
  GpuProbeFace face = faces[texel.z];
  // The view's pixel that looks along this cube texel (plan.cpp: the views mirror the cube).
  ivec3 pixel = ivec3(size.x - 1 - texel.x, texel.y, texel.z);
  float depth = texelFetch(depth_map, pixel, 0).r;
  vec2 ndc = (vec2(pixel.xy) + 0.5) / vec2(size) * 2.0 - 1.0;
  if (depth <= 0.0) {
    // The ray through the texel, from the eye to its point on the near plane (device depth 1).
    vec4 near_point = view.inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 ray = normalize(near_point.xyz / near_point.w - view.eye.xyz);
    vec3 radiance = HAS_SKY != 0u ? textureLod(sky_cube, ray, 0.0).rgb : sky.rgb;
    imageStore(faces_out, texel, vec4(nearest_half(radiance), 1.0));
    return;
  }
  vec4 p = view.inverse_view_projection * vec4(ndc, depth, 1.0);
  vec3 position = p.xyz / p.w;  // camera-relative world
  vec4 albedo_flags = texelFetch(albedo_map, pixel, 0);
  vec3 albedo = albedo_flags.rgb;
  vec3 emitted = texelFetch(emissive_map, pixel, 0).rgb;
  if (albedo_flags.a > 0.0) {  // unlit: the base colour is the result
    imageStore(faces_out, texel, vec4(nearest_half(albedo + emitted), 1.0));
    return;
  }
  vec3 v = normalize(view.eye.xyz - position);
  vec3 n = normalize(texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0);
  vec4 material = texelFetch(material_map, pixel, 0);
  float metallic = material.r;
  float roughness = max(material.g, min_roughness);
  float alpha = roughness * roughness;

  vec3 diffuse = vec3(0.0), specular = vec3(0.0);
  if (frame.sun_direction.w > 0.0) {
    vec3 e = frame.sun_radiance.rgb * sun_visibility(position, n);
    diffuse += diffuse_term(n, -frame.sun_direction.xyz, e, albedo, metallic);
    specular += specular_term(n, v, -frame.sun_direction.xyz, e, albedo, metallic, alpha);
  }
  for (uint i = face.first_light; i < face.first_light + face.lights; ++i)
    add_direct_light(lights[i], position, n, v, albedo, metallic, alpha, 1.0, tube_samples, diffuse, specular);

  // lighting.composite's sum: it reads the material's roughness, not the floored one.
  float visibility = texelFetch(occlusion_map, pixel, 0).r;
  specular = nearest_half(specular);
  vec3 indirect_diffuse = ambient.rgb * albedo * (1.0 - metallic) * visibility;
  if (HAS_SKY != 0u) {
    vec3 r = dominant_direction(n, v, material.g);
    vec3 prefiltered = textureLod(specular_cube, r, material.g * float(kSkySpecularMips - 1u)).rgb;
    Indirect sky_light = environment_light(n, v, r, vec3(0.0), albedo, metallic, material.g, visibility, 1.0, 1.0,
                                           multiple_scattering != 0u, prefiltered,
                                           irradiance_over_pi(n) * topdown_sky_visibility(position, n));
    indirect_diffuse += sky_light.diffuse;
    specular += sky_light.specular;
  }
  // The composite's sum of the halves lighting.deferred stored.
  vec3 lit = nearest_half(diffuse) + specular + emitted + indirect_diffuse;
  imageStore(faces_out, texel, vec4(nearest_half(lit), 1.0));
}
