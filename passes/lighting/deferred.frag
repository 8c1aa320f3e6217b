#version 460
// Every light at every pixel (the clustered, tiled version replaces this pass later).
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "brdf.glsl"
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

// glTF's recommended smooth window so a light's reach ends at its range.
float range_window(float distance, float range) {
  if (range <= 0.0) return 1.0;
  float r = distance / range;
  float w = clamp(1.0 - r * r * r * r, 0.0, 1.0);
  return w * w;
}

float spot_factor(GpuLight light, vec3 to_light) {
  float cos_outer = light.direction_cos_outer.w, cos_inner = light.cos_inner.x;
  float cd = dot(light.direction_cos_outer.xyz, -to_light);
  float t = clamp((cd - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0.0, 1.0);
  return t * t;
}

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

  for (uint i = 0u; i < frame.counts.x; ++i) {
    GpuLight light = lights[i];
    uint type = uint(light.position_type.w);
    vec3 radiance = light.color_range.rgb * intensity_scale;
    float range = light.color_range.w;
    if (type == kLightDirectional) {
      diffuse += diffuse_term(n, -light.direction_cos_outer.xyz, radiance, albedo, metallic);
      specular += specular_term(n, v, -light.direction_cos_outer.xyz, radiance, albedo, metallic, alpha);
    } else if (type == kLightTube) {
      // A line light of `radiance` candela per metre. Diffuse: the segment integrated with
      // tube_samples midpoint samples. Specular: Karis' representative point (the segment point
      // closest to the reflection ray) with the widened lobe renormalised.
      vec3 a = light.position_type.xyz - position, b = light.end_radius.xyz - position;
      vec3 ab = b - a;
      float len = length(ab);
      // Beyond its range from the nearest point of the segment, a tube adds nothing.
      vec3 nearest = a + ab * clamp(-dot(a, ab) / max(dot(ab, ab), 1e-8), 0.0, 1.0);
      if (range > 0.0 && dot(nearest, nearest) >= range * range) continue;
      int samples = max(tube_samples, 1);
      float irradiance = 0.0;  // per unit radiance: Σ n·l / d² × window × segment share
      for (int s = 0; s < samples; ++s) {
        vec3 q = a + ab * ((float(s) + 0.5) / float(samples));
        float d2 = max(dot(q, q), 1e-8);
        float d = sqrt(d2);
        irradiance += max(dot(n, q / d), 0.0) / d2 * range_window(d, range);
      }
      diffuse += albedo * (1.0 - metallic) * (1.0 / PI) * radiance * (irradiance * len / float(samples));
      vec3 r = reflect(-v, n);
      float rab = dot(r, ab);
      float t = clamp((dot(r, a) * rab - dot(a, ab)) / max(dot(ab, ab) - rab * rab, 1e-8), 0.0, 1.0);
      vec3 q = a + ab * t;
      float d2 = max(dot(q, q), 1e-8);
      float d = sqrt(d2);
      float widened = clamp(alpha + 0.5 * len / (2.0 * d), 0.0, 1.0);
      // A zero-length tube on a surface with no roughness floor gives 0/0.
      float normalisation = alpha / max(widened, 1e-30);
      vec3 e = radiance * len / d2 * range_window(d, range);
      specular += specular_term(n, v, q / d, e, albedo, metallic, alpha) * normalisation;
    } else {
      vec3 to_light = light.position_type.xyz - position;
      float d2 = max(dot(to_light, to_light), 1e-8);
      if (range > 0.0 && d2 >= range * range) continue;
      float d = sqrt(d2);
      vec3 l = to_light / d;
      float attenuation = range_window(d, range) / d2;
      if (type == kLightSpot) attenuation *= spot_factor(light, l);
      if (attenuation <= 0.0) continue;
      diffuse += diffuse_term(n, l, radiance * attenuation, albedo, metallic);
      specular += specular_term(n, v, l, radiance * attenuation, albedo, metallic, alpha);
    }
  }
  out_diffuse = vec4(nearest_half(diffuse), 1.0);
  out_specular = vec4(nearest_half(specular), 1.0);
}
