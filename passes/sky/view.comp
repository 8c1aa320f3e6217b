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
#include "march.glsl"

float sq(float x) { return x * x; }

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
  float h = camera_height_km(atmosphere.light.w);
  float cos_zenith, cos_azimuth;
  sky_view_angles((vec2(texel) + 0.5) / vec2(size), vec2(size), h, cos_zenith, cos_azimuth);
  float sin_zenith = sqrt(max(1.0 - cos_zenith * cos_zenith, 0.0));
  vec3 direction =
      vec3(sin_zenith * cos_azimuth, cos_zenith, sin_zenith * sqrt(max(1.0 - cos_azimuth * cos_azimuth, 0.0)));
  vec3 to_light_world = -frame.sun_direction.xyz;
  vec3 light = vec3(sqrt(max(1.0 - to_light_world.y * to_light_world.y, 0.0)), to_light_world.y, 0.0);
  ViewRay ray = view_ray_from(h, direction, light);

  float ground_distance;
  bool ground = meets_ground(h, cos_zenith, ground_distance);
  float length_km = ground ? ground_distance : distance_to_top(h, cos_zenith);
  March march = march_start();
  // Steps grow quadratically from the camera (Hillaire 2020): the air is densest near it,
  // whether the ray climbs or runs along the ground (whose height grows with t²).
  for (uint i = 0u; i < samples; ++i)
    march_step(ray, length_km * sq(float(i) / float(samples)), length_km * sq(float(i + 1u) / float(samples)), march);
  imageStore(lut, texel, vec4(nearest_half(march.radiance * frame.sun_radiance.rgb), 1.0));
}
