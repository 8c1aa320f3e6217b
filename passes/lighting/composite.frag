#version 460
#include "../frame/types.glsl"

layout(set = 0, binding = 0) uniform sampler2D diffuse_map;
layout(set = 0, binding = 1) uniform sampler2D specular_map;
layout(set = 0, binding = 2) uniform sampler2D albedo_map;
layout(set = 0, binding = 3) uniform sampler2D material_map;
layout(set = 0, binding = 4) uniform sampler2D emissive_map;
layout(set = 0, binding = 5) uniform sampler2D depth_map;

layout(push_constant) uniform Params {
  vec4 ambient;  // rgb radiance of the uniform ambient term
  vec4 sky;      // rgb radiance where nothing was drawn
};

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_lit;

const float HALF_MAX = 65504.0;

// The half float nearest to x (0 ≤ x ≤ HALF_MAX), so that the RGBA16F store is exact: Vulkan
// leaves its rounding open and lavapipe truncates, which costs up to a whole ULP. Adding c, a
// float whose own ULP is the half-float ULP at x, rounds x to that step (to nearest even);
// subtracting it back is exact. `precise` keeps the compiler from folding the two.
vec3 nearest_half(vec3 x) {
  ivec3 exponent = max(ivec3(floatBitsToUint(x) >> 23) - 127, ivec3(-14));  // subnormal halves share 2^-24
  vec3 c = uintBitsToFloat(uvec3(exponent - 10 + 23 + 127) << 23);
  precise vec3 rounded = (x + c) - c;
  return rounded;
}

vec3 radiance(ivec2 pixel) {
  if (texelFetch(depth_map, pixel, 0).r <= 0.0) return sky.rgb;
  vec4 albedo = texelFetch(albedo_map, pixel, 0);
  vec3 emitted = texelFetch(emissive_map, pixel, 0).rgb;
  if (albedo.a > 0.0) return albedo.rgb + emitted;  // unlit: the base colour is the result
  float metallic = texelFetch(material_map, pixel, 0).r;
  return texelFetch(diffuse_map, pixel, 0).rgb + texelFetch(specular_map, pixel, 0).rgb + emitted +
         ambient.rgb * albedo.rgb * (1.0 - metallic);
}

void main() {
  // Beyond HALF_MAX a round-to-nearest store would write +Inf, which every later pass carries.
  out_lit = vec4(nearest_half(min(radiance(ivec2(gl_FragCoord.xy)), HALF_MAX)), 1.0);
}
