#version 460
// gi.volume, one box of gi.refresh per dispatch, a cell per invocation: the irradiance about every
// normal at the cell's centre, as 9 spherical-harmonic coefficients per colour (GpuSkyIrradiance's
// form), gathered as lighting.composite gathers a point's reflections: the two nearest probes
// whose boxes hold the centre, each weighted by how deep inside its box the centre lies
// (reflection.glsl's nearest_probes()), their coefficients from probes.irradiance; the sky's
// (sky.irradiance) makes up what their weights leave, times the sky's visibility straight above
// the centre (topdown.glsl; the probes' captures see their own sky). Stored at the cell's toroidal
// texel (volume_layout.glsl.h), each half rounded to the nearest.
#include "../frame/half.glsl"
#include "../probes/capture_layout.glsl.h"
#include "../probes/paraboloid.glsl.h"
#include "../shadow/topdown_layout.glsl.h"
#include "../sky/ibl.glsl.h"
#include "volume_layout.glsl.h"

layout(local_size_x = kGiVolumeGroupSide, local_size_y = kGiVolumeGroupSide, local_size_z = kGiVolumeGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(gi_volume_data)) uniform VolumeBlock { GpuGiVolume volume; };
layout(std430, set = 0, binding = NC_BINDING(sky_irradiance)) readonly buffer SkyBlock { GpuSkyIrradiance sky; };
layout(std140, set = 0, binding = NC_BINDING(shadow_topdown_data)) uniform TopdownBlock { GpuTopdown topdown; };
layout(set = 0, binding = NC_BINDING(shadow_topdown)) uniform sampler2D topdown_map;
layout(set = 0, binding = NC_BINDING(gi_volume), rgba16f) uniform writeonly image3D cells_out;
layout(push_constant) uniform GiVolumeConstants { NC_BLOCK_MEMBERS(NC_GI_VOLUME_CONSTANTS_FIELDS) };

#if defined(NC_BINDING_probes_slots) && defined(NC_BINDING_probes_irradiance)
#define NC_PROBE_SLOTS
layout(std430, set = 0, binding = NC_BINDING(probes_slots)) readonly buffer ProbeSlotBlock { GpuProbeSlot slots[]; };
layout(std430, set = 0, binding = NC_BINDING(probes_irradiance)) readonly buffer ProbeIrradianceBlock {
  GpuSkyIrradiance probe_irradiance[];
};
#include "../probes/reflection.glsl"
#endif

#include "../shadow/topdown.glsl"

void main() {
  uvec3 local = gl_GlobalInvocationID;
  if (any(greaterThanEqual(local, box_size.xyz))) return;
  ivec3 cell = box_min.xyz + ivec3(local);
  int cells = volume.origin_cell.w;
  vec3 centre = volume.origin.xyz + (vec3(cell - volume.origin_cell.xyz) + 0.5) * volume.origin.w;
  float open = topdown_sky_visibility(centre, vec3(0.0, 1.0, 0.0));
  vec3 c[9];
  for (int i = 0; i < 9; ++i) c[i] = sky.coefficients[i].rgb * open;
#ifdef NC_PROBE_SLOTS
  if (box_size.w != 0u) {
    NearestProbes nearest = nearest_probes(centre, uint(box_min.w), probes.x);
    vec3 sum[9];
    for (int i = 0; i < 9; ++i) sum[i] = vec3(0.0);
    float total = 0.0;
    for (int k = 0; k < 2; ++k) {
      if (nearest.weight[k] <= 0.0) continue;
      uint slot = uint(slots[nearest.index[k]].position.w);
      for (int i = 0; i < 9; ++i) sum[i] += nearest.weight[k] * probe_irradiance[slot].coefficients[i].rgb;
      total += nearest.weight[k];
    }
    for (int i = 0; i < 9; ++i) c[i] = total > 1.0 ? sum[i] / total : sum[i] + (1.0 - total) * c[i];
  }
#endif
  ivec3 texel = ((cell % cells) + cells) % cells;
  for (int k = 0; k < int(kGiVolumeTexels); ++k) {
    vec4 packed = vec4(0.0);
    for (int m = 0; m < 4; ++m) {
      int index = 4 * k + m;
      packed[m] = index < 27 ? c[index / 3][index % 3] : 0.0;
    }
    imageStore(cells_out, ivec3(texel.xy, texel.z + k * cells), nearest_half(packed));
  }
}
