// How a local light falls off: glTF's range window and a spot's cone (KHR_lights_punctual), for
// every pass that shades local lights (lighting.tiled, lighting.deferred, probes.light, the
// LTC lines). Needs types.glsl (GpuLight).
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

// A spot's cone toward the unit vector to the light: 1 inside the inner cone, 0 outside the
// outer, between them the square of a ramp linear in the angle's cosine.
float spot_factor(GpuLight light, vec3 to_light) {
  float cos_outer = light.direction_cos_outer.w, cos_inner = light.cos_inner.x;
  float cd = dot(light.direction_cos_outer.xyz, -to_light);
  float t = clamp((cd - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0.0, 1.0);
  return t * t;
}

#endif
