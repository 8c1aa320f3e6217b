// How a local light falls off: glTF's range window and a spot's cone (KHR_lights_punctual), for
// every pass that shades local lights (lighting.tiled, lighting.deferred, probes.light, the
// LTC lines).
#ifndef NIGHTCAP_LIGHTING_LIGHT_FALLOFF_GLSL
#define NIGHTCAP_LIGHTING_LIGHT_FALLOFF_GLSL

// glTF's recommended smooth window, (1 − (d/range)⁴)², so that a light's reach ends at its range;
// 1 without a range.
float range_window(float distance, float range) {
  if (range <= 0.0) return 1.0;
  float r = distance / range;
  float w = clamp(1.0 - r * r * r * r, 0.0, 1.0);
  return w * w;
}

// A spot's cone (axis `spot_direction`, the way it shines; the cosines of its outer and inner
// half-angles) toward the unit vector to the light: 1 inside the inner cone, 0 outside the
// outer, between them the square of a ramp linear in the angle's cosine.
float spot_cone(vec3 spot_direction, float cos_outer, float cos_inner, vec3 to_light) {
  float t = clamp((dot(spot_direction, -to_light) - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0.0, 1.0);
  return t * t;
}

#endif
