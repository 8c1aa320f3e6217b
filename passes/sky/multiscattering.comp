#version 460
// sky.multiscattering: Hillaire's (2020) multiple scattering LUT. At each texel's height and
// light zenith (multiscattering_h_mu), for a light of unit illuminance: the light scattered
// twice toward the point, averaged over `directions`² directions of a sphere (isotropic phase),
// L2, with the ground's Lambertian bounce; and f, the share of light the medium around the point
// scatters back to it. Every further order is taken to scatter as the second: Psi = L2 / (1 - f),
// what sky.view adds to each sample's in-scattering, times the medium's scattering. Kept from
// the previous frame (a copy) when the atmosphere has not changed.
#include "../frame/half.glsl"
#include "atmosphere.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_transmittance)) uniform sampler2D transmittance_lut;
layout(set = 0, binding = NC_BINDING(sky_multiscattering_previous)) uniform sampler2D previous_lut;
layout(set = 0, binding = NC_BINDING(sky_multiscattering), rgba16f) uniform writeonly image2D lut;
layout(push_constant) uniform SkyLutConstants { NC_BLOCK_MEMBERS(NC_SKY_LUT_CONSTANTS_FIELDS) };

#include "atmosphere.glsl"
#include "toward_light.glsl"

void main() {
  ivec2 size = imageSize(lut);
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size))) return;
  if (has_atmosphere == 0u) {
    imageStore(lut, texel, vec4(0.0));
    return;
  }
  if (atmosphere.changed.x == 0u) {
    imageStore(lut, texel, texelFetch(previous_lut, texel, 0));
    return;
  }
  float h, mu_light;
  multiscattering_h_mu((vec2(texel) + 0.5) / vec2(size), vec2(size), h, mu_light);
  float r = ground_km() + h;
  vec3 light = vec3(sqrt(max(1.0 - mu_light * mu_light, 0.0)), mu_light, 0.0);
  const float isotropic = 1.0 / (4.0 * kSkyPi);
  vec3 second_order = vec3(0.0), transfer = vec3(0.0);
  for (uint a = 0u; a < directions; ++a) {
    for (uint b = 0u; b < directions; ++b) {
      float cos_theta = 1.0 - 2.0 * (float(b) + 0.5) / float(directions);
      float phi = 2.0 * kSkyPi * (float(a) + 0.5) / float(directions);
      float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
      vec3 direction = vec3(sin_theta * cos(phi), cos_theta, sin_theta * sin(phi));
      float ground_distance;
      bool ground = meets_ground(h, cos_theta, ground_distance);
      float length_km = ground ? ground_distance : distance_to_top(h, cos_theta);
      float cos_phase = dot(direction, light);
      float step_km = length_km / float(samples);
      vec3 throughput = vec3(1.0), scattered = vec3(0.0), back = vec3(0.0);
      for (uint i = 0u; i < samples; ++i) {
        float t = (float(i) + 0.5) * step_km;
        float h_p = height_along(h, cos_theta, t);
        float mu_p = (r * mu_light + t * cos_phase) / (ground_km() + h_p);
        Medium m = medium_at(h_p);
        vec3 scattering = m.rayleigh + m.mie;
        vec3 step_transmittance = exp(-m.extinction * step_km);
        vec3 weight = throughput * through_step(m.extinction, step_km);
        scattered += weight * scattering * toward_light(h_p, mu_p) * isotropic;
        back += weight * scattering;
        throughput *= step_transmittance;
      }
      if (ground) {
        float mu_ground = (r * mu_light + length_km * cos_phase) / ground_km();
        scattered += throughput * toward_light(0.0, mu_ground) * max(mu_ground, 0.0) * atmosphere.radii.w / kSkyPi;
      }
      second_order += scattered;
      transfer += back;
    }
  }
  // Means over the sphere, the integrals against the isotropic phase.
  float count = float(directions * directions);
  second_order /= count;
  transfer /= count;
  imageStore(lut, texel, vec4(nearest_half(second_order / (1.0 - min(transfer, vec3(0.99)))), 1.0));
}
