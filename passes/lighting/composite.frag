#version 460
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "composite.glsl.h"

layout(set = 0, binding = NC_BINDING(lighting_diffuse)) uniform sampler2D diffuse_map;
layout(set = 0, binding = NC_BINDING(lighting_specular)) uniform sampler2D specular_map;
layout(set = 0, binding = NC_BINDING(gbuffer_albedo)) uniform sampler2D albedo_map;
layout(set = 0, binding = NC_BINDING(gbuffer_material)) uniform sampler2D material_map;
layout(set = 0, binding = NC_BINDING(gbuffer_emissive)) uniform sampler2D emissive_map;
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
#ifdef NC_BINDING_ao
layout(set = 0, binding = NC_BINDING(ao)) uniform sampler2D ao_map;  // ao.bent; alpha: the visibility
#endif

layout(push_constant) uniform CompositeConstants { NC_BLOCK_MEMBERS(NC_COMPOSITE_CONSTANTS_FIELDS) };

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_lit;

vec3 radiance(ivec2 pixel) {
  if (texelFetch(depth_map, pixel, 0).r <= 0.0) return sky.rgb;
  vec4 albedo = texelFetch(albedo_map, pixel, 0);
  vec3 emitted = texelFetch(emissive_map, pixel, 0).rgb;
  if (albedo.a > 0.0) return albedo.rgb + emitted;  // unlit: the base colour is the result
  float metallic = texelFetch(material_map, pixel, 0).r;
  vec3 indirect = ambient.rgb;
#ifdef NC_BINDING_ao
  indirect *= textureLod(ao_map, in_uv, 0.0).a;
#endif
  return texelFetch(diffuse_map, pixel, 0).rgb + texelFetch(specular_map, pixel, 0).rgb + emitted +
         indirect * albedo.rgb * (1.0 - metallic);
}

void main() { out_lit = vec4(nearest_half(radiance(ivec2(gl_FragCoord.xy))), 1.0); }
