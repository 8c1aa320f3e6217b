// A view ray's march through the atmosphere, shared by sky.view (to the ground or the top) and
// sky.aerial_perspective (to each of its slices): at each step, single scattering of the light
// through sky.transmittance, with Rayleigh's and Cornette-Shanks's phase functions, plus
// sky.multiscattering's every further order (Hillaire 2020), integrated against the step's own
// extinction. Figures are for a light of unit illuminance. Needs the samplers
// `transmittance_lut` and `multiscattering_lut` and atmosphere.glsl before it.
#ifndef NIGHTCAP_SKY_MARCH_GLSL
#define NIGHTCAP_SKY_MARCH_GLSL

#include "toward_light.glsl"

vec3 multiple_scattering(float h, float mu_light) {
  vec2 uv = multiscattering_uv(h, mu_light, vec2(textureSize(multiscattering_lut, 0)));
  return textureLod(multiscattering_lut, uv, 0.0).rgb;
}

// A ray from height h along `direction`, lit from `to_light` (unit vectors in a frame whose y is
// the zenith at the ray's start).
struct ViewRay {
  float h, r, mu, light_y, cos_phase, rayleigh_p, mie_p;
};

ViewRay view_ray_from(float h, vec3 direction, vec3 to_light) {
  ViewRay ray;
  ray.h = h;
  ray.r = ground_km() + h;
  ray.mu = direction.y;
  ray.light_y = to_light.y;
  ray.cos_phase = dot(direction, to_light);
  ray.rayleigh_p = rayleigh_phase(ray.cos_phase);
  ray.mie_p = mie_phase(ray.cos_phase);
  return ray;
}

// What has reached the ray's start so far, and the transmittance and optical depth to where the
// march stands.
struct March {
  vec3 radiance, throughput, optical_depth;
};

March march_start() { return March(vec3(0.0), vec3(1.0), vec3(0.0)); }

// Adds the step from `start` to `end` km along the ray, sampled at its middle.
void march_step(ViewRay ray, float start, float end, inout March m) {
  float step_km = end - start, t = 0.5 * (start + end);
  float h_p = height_along(ray.h, ray.mu, t);
  float mu_light = (ray.r * ray.light_y + t * ray.cos_phase) / (ground_km() + h_p);
  Medium medium = medium_at(h_p);
  vec3 direct = toward_light(h_p, mu_light);
  vec3 multiple = multiple_scattering(h_p, mu_light);
  vec3 source = medium.rayleigh * (direct * ray.rayleigh_p + multiple) + medium.mie * (direct * ray.mie_p + multiple);
  m.radiance += m.throughput * source * through_step(medium.extinction, step_km);
  m.throughput *= exp(-medium.extinction * step_km);
  m.optical_depth += medium.extinction * step_km;
}

#endif
