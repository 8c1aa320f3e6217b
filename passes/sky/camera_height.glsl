// Where the camera stands in the atmosphere: the map's ground (y = 0) on the planet's surface,
// the camera `height_m` above it (sky.atmosphere's `light.w`, returned in km), kept a metre above the ground and a metre
// below the top so that every ray starts inside the atmosphere. Needs atmosphere.glsl.
#ifndef NIGHTCAP_SKY_CAMERA_HEIGHT_GLSL
#define NIGHTCAP_SKY_CAMERA_HEIGHT_GLSL

float camera_height_km(float height_m) {
  return clamp(height_m * 1e-3, 1e-3, top_km() - ground_km() - 1e-3);
}

#endif
