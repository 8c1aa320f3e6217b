#version 460
// sky.aerial_perspective: the air between the camera and what it sees (Hillaire 2020, section
// 5.4), a volume aligned with the view frustum: texel (x, y) of a slice is the view ray through
// that point of the screen, slice k of N the ray's first d = kSkyAerialDistanceKm · ((k + 1) / N)²
// km. Each is stored per km of that length, so that what the composite interpolates between slices
// is nearly constant near the camera (the air there is uniform) where the totals grow with d:
// rgb, the light the air scatters toward the camera along the length (frame.constants'
// sun_radiance times the march's unit-illuminance figure) over d; alpha, -ln of the mean over the
// three channels of the transmittance along it, over d. A thread per ray marches its slices in
// order, `samples` steps a slice; a ray that meets the planet's surface ends there. Not shadowed:
// the air behind a tower is lit as in the open.
#include "../frame/types.glsl"
#include "../frame/half.glsl"
#include "atmosphere.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_transmittance)) uniform sampler2D transmittance_lut;
layout(set = 0, binding = NC_BINDING(sky_multiscattering)) uniform sampler2D multiscattering_lut;
layout(set = 0, binding = NC_BINDING(sky_aerial_perspective), rgba16f) uniform writeonly image3D volume;
layout(push_constant) uniform SkyLutConstants { NC_BLOCK_MEMBERS(NC_SKY_LUT_CONSTANTS_FIELDS) };

#include "atmosphere.glsl"
#include "camera_height.glsl"
#include "march.glsl"

void main() {
  ivec3 size = imageSize(volume);
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size.xy))) return;
  if (has_atmosphere == 0u) {
    // The clear value: no air.
    for (int slice = 0; slice < size.z; ++slice) imageStore(volume, ivec3(texel, slice), vec4(0.0));
    return;
  }
  // The view ray through the texel's centre on the screen, world-oriented (y the zenith).
  vec2 ndc = (vec2(texel) + 0.5) / vec2(size.xy) * 2.0 - 1.0;
  vec4 near_point = camera.inverse_view_projection * vec4(ndc, 1.0, 1.0);
  vec3 direction = normalize(near_point.xyz / near_point.w);
  ViewRay ray = view_ray_from(camera_height_km(atmosphere.light.w), direction, -frame.sun_direction.xyz);
  // A ray into the planet stops at its surface: the slices beyond hold the air up to it.
  float ground_distance;
  float ray_end = meets_ground(ray.h, ray.mu, ground_distance) ? ground_distance : kSkyAerialDistanceKm;
  March march = march_start();
  float start = 0.0;
  for (int slice = 0; slice < size.z; ++slice) {
    float fraction = float(slice + 1) / float(size.z);
    float end = min(kSkyAerialDistanceKm * fraction * fraction, ray_end);
    for (uint i = 0u; i < samples; ++i)
      march_step(ray, mix(start, end, float(i) / float(samples)), mix(start, end, float(i + 1u) / float(samples)),
                 march);
    start = end;
    // 1 - the mean transmittance, and its -ln, each by its series where the closed forms would
    // lose the digits of a few metres of air.
    vec3 x = march.optical_depth;
    vec3 absorbed = mix(1.0 - exp(-x), x * (1.0 - x * (0.5 - x / 6.0)), lessThan(x, vec3(1e-2)));
    float y = (absorbed.r + absorbed.g + absorbed.b) / 3.0;
    float depth = y < 1e-3 ? y * (1.0 + y * (0.5 + y / 3.0)) : -log(1.0 - y);
    float length_km = max(end, 1e-9);
    vec3 in_scattered = nearest_half(march.radiance * frame.sun_radiance.rgb / length_km);
    imageStore(volume, ivec3(texel, slice), vec4(in_scattered, nearest_half(vec3(depth / length_km)).x));
  }
}
