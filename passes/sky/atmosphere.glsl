// The atmosphere's optics and the sky LUTs' parameterisations, shared by the sky's shaders and
// lighting.composite (Hillaire 2020; the transmittance mapping is Bruneton's, 2017). The caller
// declares GpuAtmosphere `atmosphere` (atmosphere.glsl.h) before including this file. Points are
// relative to the planet's centre, in kilometres. A point's radius r in float is good to half a
// metre, so r² - ground² (and the horizon with it) is not: functions take the height h above the
// ground beside r and form that difference as h (2 ground + h).
#ifndef NIGHTCAP_SKY_ATMOSPHERE_GLSL
#define NIGHTCAP_SKY_ATMOSPHERE_GLSL

const float kSkyPi = 3.14159265358979;

float ground_km() { return atmosphere.radii.x; }
float top_km() { return atmosphere.radii.y; }

struct Medium {
  vec3 rayleigh;     // scattering
  vec3 mie;          // scattering
  vec3 extinction;   // of the three constituents
};

// The medium at `height` km above the ground.
Medium medium_at(float height) {
  float h = max(height, 0.0);
  float rayleigh_density = exp(-h / atmosphere.rayleigh.w);
  float mie_density = exp(-h / atmosphere.mie_scattering.w);
  float ozone_density = max(0.0, 1.0 - abs(h - atmosphere.ozone.w) / atmosphere.radii.z);
  Medium m;
  m.rayleigh = atmosphere.rayleigh.rgb * rayleigh_density;
  m.mie = atmosphere.mie_scattering.rgb * mie_density;
  m.extinction = m.rayleigh + atmosphere.mie_extinction.rgb * mie_density + atmosphere.ozone.rgb * ozone_density;
  return m;
}

// ∫ exp(-extinction s) ds over a step: what the step's in-scattering is weighted by when it is
// integrated against the step's own extinction (Hillaire 2015). (1 - exp(-x)) / x loses every
// digit in float for a short step (x below 1e-3, a few metres of air), where the series holds.
vec3 through_step(vec3 extinction, float step_km) {
  vec3 x = extinction * step_km;
  vec3 series = 1.0 - x * (0.5 - x / 6.0);
  vec3 closed = (1.0 - exp(-x)) / max(x, vec3(1e-30));
  return step_km * mix(closed, series, lessThan(x, vec3(1e-2)));
}

float rayleigh_phase(float cos_angle) { return 3.0 / (16.0 * kSkyPi) * (1.0 + cos_angle * cos_angle); }

// Cornette and Shanks's phase function, with g = atmosphere.mie_extinction.w.
float mie_phase(float cos_angle) {
  float g = atmosphere.mie_extinction.w;
  float k = 3.0 / (8.0 * kSkyPi) * (1.0 - g * g) / (2.0 + g * g);
  return k * (1.0 + cos_angle * cos_angle) / pow(max(1.0 + g * g - 2.0 * g * cos_angle, 1e-6), 1.5);
}

// r² - ground², from the height.
float squared_above_ground(float h) { return h * (2.0 * ground_km() + h); }

// From a point at height h along a ray whose cosine with the local zenith is mu: the distance to
// where the ray leaves the atmosphere's top.
float distance_to_top(float h, float mu) {
  float r = ground_km() + h;
  float discriminant = r * r * (mu * mu - 1.0) + top_km() * top_km();
  return max(0.0, -r * mu + sqrt(max(discriminant, 0.0)));
}

// Whether the ray meets the ground, and the distance to it.
bool meets_ground(float h, float mu, out float distance) {
  float r = ground_km() + h;
  float discriminant = r * r * mu * mu - squared_above_ground(h);
  // -r mu - sqrt(discriminant), without the cancellation of two near-equal terms.
  distance = squared_above_ground(h) / max(-r * mu + sqrt(max(discriminant, 0.0)), 1e-30);
  return mu < 0.0 && discriminant >= 0.0;
}

// The height t km along a ray from height h with zenith cosine mu.
float height_along(float h, float mu, float t) {
  float r = ground_km() + h;
  float above = t * t + 2.0 * r * mu * t + squared_above_ground(h);  // r_t² - ground²
  return above / (sqrt(max(above + ground_km() * ground_km(), 0.0)) + ground_km());
}

// A texel-centre coordinate in [0.5/n, 1 - 0.5/n] from x in [0, 1], and back: the first and
// last texels hold x = 0 and x = 1 exactly.
float texel_coordinate(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }
float unit_of_texel_coordinate(float u, float n) { return (u - 0.5 / n) / (1.0 - 1.0 / n); }

// sky.transmittance: u maps the distance to the top between its least and greatest at the
// height, v the distance to the horizon; rays that meet the ground are not in it.
vec2 transmittance_uv(float h, float mu, vec2 size) {
  float horizon = sqrt(top_km() * top_km() - ground_km() * ground_km());
  float rho = sqrt(max(squared_above_ground(h), 0.0));
  float d = distance_to_top(h, mu);
  float d_min = top_km() - ground_km() - h, d_max = rho + horizon;
  float x_mu = d_max > d_min ? (d - d_min) / (d_max - d_min) : 0.0;
  return vec2(texel_coordinate(x_mu, size.x), texel_coordinate(rho / horizon, size.y));
}

void transmittance_h_mu(vec2 uv, vec2 size, out float h, out float mu) {
  float x_mu = unit_of_texel_coordinate(uv.x, size.x), x_r = unit_of_texel_coordinate(uv.y, size.y);
  float horizon = sqrt(top_km() * top_km() - ground_km() * ground_km());
  float rho = horizon * x_r;
  float r = sqrt(rho * rho + ground_km() * ground_km());
  h = rho * rho / (r + ground_km());
  float d_min = top_km() - ground_km() - h, d_max = rho + horizon;
  float d = d_min + x_mu * (d_max - d_min);
  mu = d == 0.0 ? 1.0 : clamp((horizon * horizon - rho * rho - d * d) / (2.0 * r * d), -1.0, 1.0);
}

// sky.multiscattering: u the cosine of the light's zenith angle, v the height.
vec2 multiscattering_uv(float h, float mu_light, vec2 size) {
  float x_h = clamp(h / (top_km() - ground_km()), 0.0, 1.0);
  return vec2(texel_coordinate(clamp(mu_light * 0.5 + 0.5, 0.0, 1.0), size.x), texel_coordinate(x_h, size.y));
}

void multiscattering_h_mu(vec2 uv, vec2 size, out float h, out float mu_light) {
  mu_light = unit_of_texel_coordinate(uv.x, size.x) * 2.0 - 1.0;
  h = unit_of_texel_coordinate(uv.y, size.y) * (top_km() - ground_km());
}

// sky.view, seen from height h: u the cosine of the azimuth between the view and the light
// (1 toward the light, squared toward it for detail around the sun), v the view's zenith angle,
// the upper half of the texture above the horizon and the lower below it, each squared toward
// the horizon, where the sky changes fastest.

// The angle between the nadir and the horizon, seen from height h.
float horizon_from_nadir(float h) {
  return acos(clamp(sqrt(max(squared_above_ground(h), 0.0)) / (ground_km() + h), -1.0, 1.0));
}

vec2 sky_view_uv(float h, float cos_zenith, float cos_azimuth, vec2 size) {
  float below = horizon_from_nadir(h);
  float zenith_to_horizon = kSkyPi - below;
  float zenith = acos(clamp(cos_zenith, -1.0, 1.0));
  float v;
  if (zenith <= zenith_to_horizon) {
    v = 0.5 * (1.0 - sqrt(max(1.0 - zenith / zenith_to_horizon, 0.0)));
  } else {
    v = 0.5 + 0.5 * sqrt(clamp((zenith - zenith_to_horizon) / max(below, 1e-6), 0.0, 1.0));
  }
  float u = sqrt(clamp(0.5 - 0.5 * cos_azimuth, 0.0, 1.0));
  return vec2(texel_coordinate(u, size.x), texel_coordinate(v, size.y));
}

void sky_view_angles(vec2 uv, vec2 size, float h, out float cos_zenith, out float cos_azimuth) {
  float u = unit_of_texel_coordinate(uv.x, size.x), v = unit_of_texel_coordinate(uv.y, size.y);
  float below = horizon_from_nadir(h);
  float zenith_to_horizon = kSkyPi - below;
  float zenith;
  if (v < 0.5) {
    float s = 1.0 - 2.0 * v;
    zenith = zenith_to_horizon * (1.0 - s * s);
  } else {
    float s = 2.0 * v - 1.0;
    zenith = zenith_to_horizon + below * s * s;
  }
  cos_zenith = cos(zenith);
  cos_azimuth = 1.0 - 2.0 * u * u;
}

#endif
