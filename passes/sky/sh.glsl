// The real spherical harmonics of bands 0–2 at a unit direction, in sky.irradiance's order
// (passes/sky/ibl.glsl.h), and the band factors of the clamped cosine's convolution over π.
#ifndef NIGHTCAP_SKY_SH_GLSL
#define NIGHTCAP_SKY_SH_GLSL

void sh_basis(vec3 d, out float y[9]) {
  y[0] = 0.282094792;
  y[1] = 0.488602512 * d.y;
  y[2] = 0.488602512 * d.z;
  y[3] = 0.488602512 * d.x;
  y[4] = 1.092548431 * d.x * d.y;
  y[5] = 1.092548431 * d.y * d.z;
  y[6] = 0.315391565 * (3.0 * d.z * d.z - 1.0);
  y[7] = 1.092548431 * d.x * d.z;
  y[8] = 0.546274215 * (d.x * d.x - d.y * d.y);
}

// Â_l / π for the clamped cosine (π, 2π/3, π/4).
float sh_cosine_band(int i) { return i == 0 ? 1.0 : (i < 4 ? 2.0 / 3.0 : 0.25); }

#endif
