#version 460
// Every light at every pixel (the clustered, tiled version replaces this pass later).
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "brdf.glsl"
#include "direct_light.glsl"
#include "deferred.glsl.h"

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std430, set = 0, binding = NC_BINDING(frame_lights)) readonly buffer LightBlock { GpuLight lights[]; };
layout(set = 0, binding = NC_BINDING(gbuffer_albedo)) uniform sampler2D albedo_map;
layout(set = 0, binding = NC_BINDING(gbuffer_normal)) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(gbuffer_material)) uniform sampler2D material_map;
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;

layout(push_constant) uniform DeferredConstants { NC_BLOCK_MEMBERS(NC_DEFERRED_CONSTANTS_FIELDS) };

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_diffuse;
layout(location = 1) out vec4 out_specular;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(depth_map, pixel, 0).r;
  out_diffuse = vec4(0.0);
  out_specular = vec4(0.0);
  vec4 albedo_flags = texelFetch(albedo_map, pixel, 0);
  if (depth <= 0.0 || albedo_flags.a > 0.0) return;  // sky, or unlit (composite adds it)

  vec2 ndc = (vec2(pixel) + 0.5) * camera.viewport.zw * 2.0 - 1.0;
  vec4 p = camera.inverse_view_projection * vec4(ndc, depth, 1.0);
  vec3 position = p.xyz / p.w;  // camera-relative world
  vec3 v = normalize(camera.eye.xyz - position);
  vec3 n = normalize(texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0);
  vec4 material = texelFetch(material_map, pixel, 0);
  vec3 albedo = albedo_flags.rgb;
  float metallic = material.r;
  float roughness = max(material.g, min_roughness);
  float alpha = roughness * roughness;

  vec3 diffuse = vec3(0.0), specular = vec3(0.0);
  if (frame.sun_direction.w > 0.0) {
    vec3 e = frame.sun_radiance.rgb * intensity_scale;
    diffuse += diffuse_term(n, -frame.sun_direction.xyz, e, albedo, metallic);
    specular += specular_term(n, v, -frame.sun_direction.xyz, e, albedo, metallic, alpha);
  }

  for (uint i = 0u; i < frame.counts.x; ++i)
    add_direct_light(lights[i], position, n, v, albedo, metallic, alpha, intensity_scale, tube_samples, diffuse,
                     specular);
  out_diffuse = vec4(nearest_half(diffuse), 1.0);
  out_specular = vec4(nearest_half(specular), 1.0);
}
