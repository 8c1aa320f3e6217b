#version 460
// probes.irradiance, one captured probe per dispatch: its cube of probes.faces projected on bands
// 0–2 and convolved with the clamped cosine over π, as sky.irradiance does the sky's
// (sh_projection.glsl), into its slot.
#include "../sky/ibl.glsl.h"
#include "irradiance.glsl.h"

layout(local_size_x = kSkyIrradianceGroup) in;

layout(set = 0, binding = NC_BINDING(probes_faces)) uniform samplerCubeArray faces;
layout(std430, set = 0, binding = NC_BINDING(probes_irradiance)) writeonly buffer IrradianceBlock {
  GpuSkyIrradiance slots[];
};
layout(push_constant) uniform ProbeIrradianceConstants { NC_BLOCK_MEMBERS(NC_PROBE_IRRADIANCE_CONSTANTS_FIELDS) };

#include "../sky/sh.glsl"
#define SH_PROJECTION_SOURCE(direction) textureLod(faces, vec4(direction, float(capture)), float(level)).rgb
#include "../sky/sh_projection.glsl"

void main() {
  uint thread = gl_LocalInvocationIndex;
  project_cube_level(textureSize(faces, int(level)).x);
  if (thread < 9u) slots[slot].coefficients[thread] = vec4(sh_projected(int(thread)), 0.0);
}
