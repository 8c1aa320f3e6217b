#version 460
// sky.view: the sky's radiance around the camera (Hillaire 2020, section 5.3), parameterised by
// sky_view_uv around the direction of the frame's directional light (the sun, or the moon at
// night). Each texel marches its view ray through the atmosphere in `samples` steps growing
// quadratically from the camera, to the ground or the atmosphere's top: single scattering of the
// light through sky.transmittance, with Rayleigh's and Cornette-Shanks's phase functions, plus
// sky.multiscattering's every further order. Radiance: the light's (frame.constants'
// sun_radiance) times the LUTs' unit-illuminance figures. The ground's own radiance is not in it
// (the scene draws the ground).
#include "../frame/types.glsl"
#include "../frame/half.glsl"
#include "atmosphere.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_transmittance)) uniform sampler2D transmittance_lut;
layout(set = 0, binding = NC_BINDING(sky_multiscattering)) uniform sampler2D multiscattering_lut;
layout(set = 0, binding = NC_BINDING(sky_view_previous)) uniform sampler2D previous_lut;
layout(set = 0, binding = NC_BINDING(sky_view), rgba16f) uniform writeonly image2D lut;
layout(push_constant) uniform SkyLutConstants { NC_BLOCK_MEMBERS(NC_SKY_LUT_CONSTANTS_FIELDS) };

#include "atmosphere.glsl"
#include "camera_height.glsl"

float sq(float x) { return x * x; }

// Transmittance from a point at height h toward the light (0 where the ground is in the way).
vec3 toward_light(float h, float mu_light) {
  float unused;
  if (meets_ground(h, mu_light, unused)) return vec3(0.0);
  return textureLod(transmittance_lut, transmittance_uv(h, mu_light, vec2(textureSize(transmittance_lut, 0))), 0.0).rgb;
}

vec3 multiple_scattering(float h, float mu_light) {
  return textureLod(multiscattering_lut, multiscattering_uv(h, mu_light, vec2(textureSize(multiscattering_lut, 0))), 0.0)
      .rgb;
}

void main() {
  ivec2 size = imageSize(lut);
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size))) return;
  if (has_atmosphere == 0u) {
    imageStore(lut, texel, vec4(0.0));
    return;
  }
  if (atmosphere.changed.y == 0u) {
    imageStore(lut, texel, texelFetch(previous_lut, texel, 0));
    return;
  }
  float h = camera_height_km(atmosphere.light.w), r = ground_km() + h;
  float cos_zenith, cos_azimuth;
  sky_view_angles((vec2(texel) + 0.5) / vec2(size), vec2(size), h, cos_zenith, cos_azimuth);
  float sin_zenith = sqrt(max(1.0 - cos_zenith * cos_zenith, 0.0));
  vec3 direction =
      vec3(sin_zenith * cos_azimuth, cos_zenith, sin_zenith * sqrt(max(1.0 - cos_azimuth * cos_azimuth, 0.0)));
  vec3 to_light_world = -frame.sun_direction.xyz;
  vec3 light = vec3(sqrt(max(1.0 - to_light_world.y * to_light_world.y, 0.0)), to_light_world.y, 0.0);
  float cos_phase = dot(direction, light);
  float rayleigh_p = rayleigh_phase(cos_phase), mie_p = mie_phase(cos_phase);

  float ground_distance;
  bool ground = meets_ground(h, cos_zenith, ground_distance);
  float length_km = ground ? ground_distance : distance_to_top(h, cos_zenith);
  vec3 throughput = vec3(1.0), radiance = vec3(0.0);
  for (uint i = 0u; i < samples; ++i) {
    // Steps grow quadratically from the camera (Hillaire 2020): the air is densest near it,
    // whether the ray climbs or runs along the ground (whose height grows with t²).
    float start = length_km * sq(float(i) / float(samples)), end = length_km * sq(float(i + 1u) / float(samples));
    float step_km = end - start, t = 0.5 * (start + end);
    float h_p = height_along(h, cos_zenith, t);
    float mu_light = (r * light.y + t * cos_phase) / (ground_km() + h_p);
    Medium m = medium_at(h_p);
    vec3 direct = toward_light(h_p, mu_light);
    vec3 multiple = multiple_scattering(h_p, mu_light);
    vec3 source = m.rayleigh * (direct * rayleigh_p + multiple) + m.mie * (direct * mie_p + multiple);
    vec3 step_transmittance = exp(-m.extinction * step_km);
    radiance += throughput * source * through_step(m.extinction, step_km);
    throughput *= step_transmittance;
  }
  imageStore(lut, texel, vec4(nearest_half(radiance * frame.sun_radiance.rgb), 1.0));
}
