#version 460
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "composite.glsl.h"

layout(set = 0, binding = 0) uniform sampler2D diffuse_map;
layout(set = 0, binding = 1) uniform sampler2D specular_map;
layout(set = 0, binding = 2) uniform sampler2D albedo_map;
layout(set = 0, binding = 3) uniform sampler2D material_map;
layout(set = 0, binding = 4) uniform sampler2D emissive_map;
layout(set = 0, binding = 5) uniform sampler2D depth_map;

layout(push_constant) uniform CompositeConstants { NC_BLOCK_MEMBERS(NC_COMPOSITE_CONSTANTS_FIELDS) };

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_lit;

vec3 radiance(ivec2 pixel) {
  if (texelFetch(depth_map, pixel, 0).r <= 0.0) return sky.rgb;
  vec4 albedo = texelFetch(albedo_map, pixel, 0);
  vec3 emitted = texelFetch(emissive_map, pixel, 0).rgb;
  if (albedo.a > 0.0) return albedo.rgb + emitted;  // unlit: the base colour is the result
  float metallic = texelFetch(material_map, pixel, 0).r;
  return texelFetch(diffuse_map, pixel, 0).rgb + texelFetch(specular_map, pixel, 0).rgb + emitted +
         ambient.rgb * albedo.rgb * (1.0 - metallic);
}

void main() { out_lit = vec4(nearest_half(radiance(ivec2(gl_FragCoord.xy))), 1.0); }
