// The sky's radiance along a world direction, looked up in sky.view: by the direction's zenith
// angle and its azimuth from the frame's directional light, seen from the height sky.atmosphere
// recorded for the camera (the one sky.view was computed for). Needs
// `frame` (GpuFrameConstants), `atmosphere` and the sampler `sky_view_lut`, and atmosphere.glsl
// and camera_height.glsl before it.
#ifndef NIGHTCAP_SKY_VIEW_LOOKUP_GLSL
#define NIGHTCAP_SKY_VIEW_LOOKUP_GLSL

vec3 sky_view_radiance(vec3 direction) {
  vec3 to_light = -frame.sun_direction.xyz;
  vec2 view_flat = direction.xz, light_flat = to_light.xz;
  float cos_azimuth = 1.0;
  if (dot(view_flat, view_flat) > 1e-12 && dot(light_flat, light_flat) > 1e-12)
    cos_azimuth = dot(normalize(view_flat), normalize(light_flat));
  vec2 uv = sky_view_uv(camera_height_km(atmosphere.light.w), direction.y, cos_azimuth,
                        vec2(textureSize(sky_view_lut, 0)));
  return textureLod(sky_view_lut, uv, 0.0).rgb;
}

#endif
