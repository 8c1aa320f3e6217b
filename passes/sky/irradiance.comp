#version 460
// sky.irradiance: one workgroup projects a level of sky.cubemap (`source_level`, the first no
// wider than kSkyIrradianceFace) on the spherical harmonics of bands 0–2 and convolves the
// projection with the clamped cosine over π (sh_projection.glsl). Copied from the previous
// frame's when sky.atmosphere says the sky seen from the camera did not change.
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

#include "sh.glsl"
#define SH_PROJECTION_SOURCE(direction) textureLod(sky_cube, direction, float(source_level)).rgb
#include "sh_projection.glsl"

void main() {
  uint thread = gl_LocalInvocationIndex;
  if (has_atmosphere != 0u && atmosphere.changed.y == 0u) {
    if (thread < 9u) irradiance.coefficients[thread] = previous_irradiance.coefficients[thread];
    return;
  }
  if (has_atmosphere == 0u) {
    if (thread < 9u) irradiance.coefficients[thread] = vec4(0.0);
    return;
  }
  project_cube_level(textureSize(sky_cube, int(source_level)).x);
  if (thread < 9u) irradiance.coefficients[thread] = vec4(sh_projected(int(thread)), 0.0);
}
