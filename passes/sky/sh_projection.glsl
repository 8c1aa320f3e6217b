// A cube map's level projected on the spherical harmonics of bands 0–2 by one workgroup of
// kSkyIrradianceGroup invocations, each texel weighted by the solid angle it subtends: what
// sky.irradiance does with the sky's cube and probes.irradiance with a probe's capture. Needs
// sh.glsl and SH_PROJECTION_SOURCE(direction) defined: the radiance of the level projected along
// a direction.
#ifndef NIGHTCAP_SKY_SH_PROJECTION_GLSL
#define NIGHTCAP_SKY_SH_PROJECTION_GLSL

#include "cube.glsl"

shared vec3 sh_partial[kSkyIrradianceGroup][9];

// The solid angle of the part of a face (at distance 1) from its centre to (x, y).
float sh_corner_area(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }

// Every invocation of the workgroup calls it: afterwards sh_projected(i) is the projection's i-th
// coefficient convolved with the clamped cosine and divided by π (ibl.glsl.h), in every one.
void project_cube_level(int size) {
  uint thread = gl_LocalInvocationIndex;
  vec3 sum[9];
  for (int i = 0; i < 9; ++i) sum[i] = vec3(0.0);
  uint texels = uint(size * size * 6);
  float step_st = 2.0 / float(size);
  for (uint index = thread; index < texels; index += kSkyIrradianceGroup) {
    uint face = index / uint(size * size);
    ivec2 texel = ivec2(index % uint(size), (index / uint(size)) % uint(size));
    vec2 low = vec2(texel) * step_st - 1.0, high = low + step_st;
    float solid_angle = sh_corner_area(low.x, low.y) - sh_corner_area(low.x, high.y) -
                        sh_corner_area(high.x, low.y) + sh_corner_area(high.x, high.y);
    vec3 direction = cube_texel_direction(face, texel, size);
    vec3 radiance = SH_PROJECTION_SOURCE(direction) * solid_angle;
    float y[9];
    sh_basis(direction, y);
    for (int i = 0; i < 9; ++i) sum[i] += radiance * y[i];
  }
  for (int i = 0; i < 9; ++i) sh_partial[thread][i] = sum[i];
  barrier();
  for (uint half_count = kSkyIrradianceGroup / 2u; half_count > 0u; half_count /= 2u) {
    if (thread < half_count)
      for (int i = 0; i < 9; ++i) sh_partial[thread][i] += sh_partial[thread + half_count][i];
    barrier();
  }
}

vec3 sh_projected(int i) { return sh_partial[0][i] * sh_cosine_band(i); }

#endif
