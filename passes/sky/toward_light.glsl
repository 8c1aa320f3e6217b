// The atmosphere's transmittance from a point toward the frame's directional light, looked up in
// sky.transmittance: shared by the passes that light the air (sky.multiscattering, sky.view,
// sky.aerial_perspective). Needs the sampler `transmittance_lut` and atmosphere.glsl before it.
#ifndef NIGHTCAP_SKY_TOWARD_LIGHT_GLSL
#define NIGHTCAP_SKY_TOWARD_LIGHT_GLSL

// From a point at height h whose zenith cosine toward the light is mu_light; 0 where the ground
// is in the way.
vec3 toward_light(float h, float mu_light) {
  float unused;
  if (meets_ground(h, mu_light, unused)) return vec3(0.0);
  return textureLod(transmittance_lut, transmittance_uv(h, mu_light, vec2(textureSize(transmittance_lut, 0))), 0.0).rgb;
}

#endif
