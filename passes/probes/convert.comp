#version 460
// probes.convert, one level of one captured probe per dispatch: each texel of the probe's two
// hemispheres in probes.array (paraboloid.glsl.h) takes the capture's radiance along its
// direction: level 0 the cube of probes.faces read there (trilinear at level 0: bilinear and
// seamless across faces), each later level the cube prefiltered with GGX at roughness
// level / (kProbeArrayMips − 1) (prefilter.glsl), reading the cube's mip chain.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "../lighting/brdf.glsl"
#include "convert.glsl.h"
#include "paraboloid.glsl.h"

layout(local_size_x = kProbeConvertGroupSide, local_size_y = kProbeConvertGroupSide) in;

layout(set = 0, binding = NC_BINDING(probes_faces)) uniform samplerCubeArray faces;
layout(set = 0, binding = NC_BINDING(probes_array), rgba16f) uniform writeonly image2DArray level_written;
layout(push_constant) uniform ProbeConvertConstants { NC_BLOCK_MEMBERS(NC_PROBE_CONVERT_CONSTANTS_FIELDS) };

#define PREFILTER_SOURCE(direction, lod) textureLod(faces, vec4(direction, float(capture)), lod).rgb
#include "../sky/prefilter.glsl"

void main() {
  ivec3 texel = ivec3(gl_GlobalInvocationID);
  int size = imageSize(level_written).x;
  if (texel.x >= size || texel.y >= size || texel.z > 1) return;
  vec2 p = (vec2(texel.xy) + 0.5) / float(size) * 2.0 - 1.0;
  vec3 d = paraboloid_direction(uint(texel.z), p);
  vec3 radiance;
  if (level == 0u) {
    radiance = PREFILTER_SOURCE(d, 0.0);
  } else {
    float roughness = float(level) / float(kProbeArrayMips - 1u);
    radiance = ggx_prefiltered(d, roughness, samples, float(textureSize(faces, 0).x), float(textureQueryLevels(faces) - 1));
  }
  imageStore(level_written, ivec3(texel.xy, 2 * int(slot) + texel.z), vec4(nearest_half(radiance), 1.0));
}
