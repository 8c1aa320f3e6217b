// The real spherical harmonics of bands 0–2 at a unit direction, in sky.irradiance's order and
// with the normalisations of ibl.glsl.h, and the band factors of the clamped cosine's convolution
// over π.
#ifndef NIGHTCAP_SKY_SH_GLSL
#define NIGHTCAP_SKY_SH_GLSL

#include "ibl.glsl.h"

void sh_basis(vec3 d, out float y[9]) {
  y[0] = kShY00;
  y[1] = kShY1 * d.y;
  y[2] = kShY1 * d.z;
  y[3] = kShY1 * d.x;
  y[4] = kShY2Cross * d.x * d.y;
  y[5] = kShY2Cross * d.y * d.z;
  y[6] = kShY20 * (3.0 * d.z * d.z - 1.0);
  y[7] = kShY2Cross * d.x * d.z;
  y[8] = kShY22 * (d.x * d.x - d.y * d.y);
}

// Â_l / π for the clamped cosine (π, 2π/3, π/4).
float sh_cosine_band(int i) { return i == 0 ? 1.0 : (i < 4 ? 2.0 / 3.0 : 0.25); }

#endif
