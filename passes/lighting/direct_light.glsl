// Direct light from one light at a surface point, as lighting.deferred shades every light at
// every pixel and the reflection probes' captures shade their lights: the light's and the
// point's positions relative to the same origin. Needs brdf.glsl and light_type.glsl.h.

#include "light_falloff.glsl"

// Adds what `light` (its radiance times `scale`) reflects toward v from the point at `position`
// with normal n to `diffuse` and `specular`; a tube's diffuse is integrated with `tube_samples`
// midpoint samples.
void add_direct_light(GpuLight light, vec3 position, vec3 n, vec3 v, vec3 albedo, float metallic, float alpha,
                      float scale, int tube_samples, inout vec3 diffuse, inout vec3 specular) {
  uint type = uint(light.position_type.w);
  vec3 radiance = light.color_range.rgb * scale;
  float range = light.color_range.w;
  if (type == kLightDirectional) {
    diffuse += diffuse_term(n, -light.direction_cos_outer.xyz, radiance, albedo, metallic);
    specular += specular_term(n, v, -light.direction_cos_outer.xyz, radiance, albedo, metallic, alpha);
  } else if (type == kLightTube) {
    // A line light of `radiance` candela per metre. Diffuse: the segment integrated with
    // tube_samples midpoint samples. Specular: Karis' representative point (the segment point
    // closest to the reflection ray) with the widened lobe renormalised.
    vec3 a = light.position_type.xyz - position, b = light.end_radius.xyz - position;
    vec3 ab = b - a;
    float len = length(ab);
    // Beyond its range from the nearest point of the segment, a tube adds nothing.
    vec3 nearest = a + ab * clamp(-dot(a, ab) / max(dot(ab, ab), 1e-8), 0.0, 1.0);
    if (range > 0.0 && dot(nearest, nearest) >= range * range) return;
    int samples = max(tube_samples, 1);
    float irradiance = 0.0;  // per unit radiance: Σ n·l / d² × window × segment share
    for (int s = 0; s < samples; ++s) {
      vec3 q = a + ab * ((float(s) + 0.5) / float(samples));
      float d2 = max(dot(q, q), 1e-8);
      float d = sqrt(d2);
      irradiance += max(dot(n, q / d), 0.0) / d2 * range_window(d, range);
    }
    diffuse += albedo * (1.0 - metallic) * (1.0 / PI) * radiance * (irradiance * len / float(samples));
    vec3 r = reflect(-v, n);
    float rab = dot(r, ab);
    float t = clamp((dot(r, a) * rab - dot(a, ab)) / max(dot(ab, ab) - rab * rab, 1e-8), 0.0, 1.0);
    vec3 q = a + ab * t;
    float d2 = max(dot(q, q), 1e-8);
    float d = sqrt(d2);
    float widened = clamp(alpha + 0.5 * len / (2.0 * d), 0.0, 1.0);
    // A zero-length tube on a surface with no roughness floor gives 0/0.
    float normalisation = alpha / max(widened, 1e-30);
    vec3 e = radiance * len / d2 * range_window(d, range);
    specular += specular_term(n, v, q / d, e, albedo, metallic, alpha) * normalisation;
  } else {
    vec3 to_light = light.position_type.xyz - position;
    float d2 = max(dot(to_light, to_light), 1e-8);
    if (range > 0.0 && d2 >= range * range) return;
    float d = sqrt(d2);
    vec3 l = to_light / d;
    float attenuation = range_window(d, range) / d2;
    if (type == kLightSpot)
      attenuation *= spot_cone(light.direction_cos_outer.xyz, light.direction_cos_outer.w, light.cos_inner.x, l);
    if (attenuation <= 0.0) return;
    diffuse += diffuse_term(n, l, radiance * attenuation, albedo, metallic);
    specular += specular_term(n, v, l, radiance * attenuation, albedo, metallic, alpha);
  }
}
