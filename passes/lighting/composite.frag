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

#if defined(NC_BINDING_sky_view) && defined(NC_BINDING_sky_atmosphere) && defined(NC_BINDING_frame_constants)
#define NC_SKY_VIEW
#include "../sky/atmosphere.glsl.h"
layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_view)) uniform sampler2D sky_view_lut;
#endif

layout(push_constant) uniform CompositeConstants { NC_BLOCK_MEMBERS(NC_COMPOSITE_CONSTANTS_FIELDS) };

#ifdef NC_SKY_VIEW
#include "../sky/atmosphere.glsl"
#include "../sky/camera_height.glsl"

// The sky seen through the pixel: sky.view looked up by the view ray's zenith angle and its
// azimuth from the light.
vec3 sky_radiance() {
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  vec4 near_point = frame.inverse_view_projection * vec4(ndc, 1.0, 1.0);
  vec3 direction = normalize(near_point.xyz / near_point.w);
  vec3 to_light = -frame.sun_direction.xyz;
  vec2 view_flat = direction.xz, light_flat = to_light.xz;
  float cos_azimuth = 1.0;
  if (dot(view_flat, view_flat) > 1e-12 && dot(light_flat, light_flat) > 1e-12)
    cos_azimuth = dot(normalize(view_flat), normalize(light_flat));
  vec2 uv = sky_view_uv(camera_height_km(frame.camera_world.y), direction.y, cos_azimuth,
                        vec2(textureSize(sky_view_lut, 0)));
  return textureLod(sky_view_lut, uv, 0.0).rgb;
}
#endif

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_lit;

vec3 radiance(ivec2 pixel) {
  if (texelFetch(depth_map, pixel, 0).r <= 0.0) {
#ifdef NC_SKY_VIEW
    if (sky_source.x != 0u) return sky_radiance();
#endif
    return sky.rgb;
  }
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
