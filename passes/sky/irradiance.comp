#version 460
// sky.irradiance: one workgroup projects a level of sky.cubemap (`source_level`, the first no
// wider than kSkyIrradianceFace) on the spherical harmonics of bands 0–2, each texel weighted by
// the solid angle it subtends, then convolves the projection with the clamped cosine and divides
// it by π (ibl.glsl.h). Copied from the previous frame's when sky.atmosphere says the sky seen
// from the camera did not change.
#include "ibl.glsl.h"

layout(local_size_x = kSkyIrradianceGroup) in;

layout(set = 0, binding = NC_BINDING(sky_cubemap)) uniform samplerCube sky_cube;
#include "atmosphere.glsl.h"
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(std430, set = 0, binding = NC_BINDING(sky_irradiance_previous)) readonly buffer PreviousBlock {
  GpuSkyIrradiance previous_irradiance;
};
layout(std430, set = 0, binding = NC_BINDING(sky_irradiance)) writeonly buffer IrradianceBlock {
  GpuSkyIrradiance irradiance;
};
layout(push_constant) uniform SkyCubeConstants { NC_BLOCK_MEMBERS(NC_SKY_CUBE_CONSTANTS_FIELDS) };

#include "cube.glsl"
#include "sh.glsl"

shared vec3 partial[kSkyIrradianceGroup][9];

// The solid angle of the part of a face (at distance 1) from its centre to (x, y).
float corner_area(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }

void main() {
  uint thread = gl_LocalInvocationIndex;
  if (has_atmosphere != 0u && atmosphere.changed.y == 0u) {
    if (thread < 9u) irradiance.coefficients[thread] = previous_irradiance.coefficients[thread];
    return;
  }
  vec3 sum[9];
  for (int i = 0; i < 9; ++i) sum[i] = vec3(0.0);
  if (has_atmosphere != 0u) {
    int size = textureSize(sky_cube, int(source_level)).x;
    uint texels = uint(size * size * 6);
    float step_st = 2.0 / float(size);
    for (uint index = thread; index < texels; index += kSkyIrradianceGroup) {
      uint face = index / uint(size * size);
      ivec2 texel = ivec2(index % uint(size), (index / uint(size)) % uint(size));
      vec2 low = vec2(texel) * step_st - 1.0, high = low + step_st;
      float solid_angle = corner_area(low.x, low.y) - corner_area(low.x, high.y) - corner_area(high.x, low.y) +
                          corner_area(high.x, high.y);
      vec3 direction = cube_texel_direction(face, texel, size);
      vec3 radiance = textureLod(sky_cube, direction, float(source_level)).rgb * solid_angle;
      float y[9];
      sh_basis(direction, y);
      for (int i = 0; i < 9; ++i) sum[i] += radiance * y[i];
    }
  }
  for (int i = 0; i < 9; ++i) partial[thread][i] = sum[i];
  barrier();
  for (uint half_count = kSkyIrradianceGroup / 2u; half_count > 0u; half_count /= 2u) {
    if (thread < half_count)
      for (int i = 0; i < 9; ++i) partial[thread][i] += partial[thread + half_count][i];
    barrier();
  }
  if (thread < 9u) irradiance.coefficients[thread] = vec4(partial[0][thread] * sh_cosine_band(int(thread)), 0.0);
}
