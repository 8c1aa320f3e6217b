#version 460
// sky.specular, one level per dispatch: sky.cubemap prefiltered with GGX for the split sum at
// perceptual roughness level / (kSkySpecularMips − 1) (prefilter.glsl says how). Level 0 (a
// mirror) is sky.cubemap read along each direction. Copied from the previous frame's when
// sky.atmosphere says the sky seen from the camera did not change.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "atmosphere.glsl.h"
#include "ibl.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_cubemap)) uniform samplerCube sky_cube;
layout(set = 0, binding = NC_BINDING(sky_specular_previous)) uniform samplerCube previous_cube;
layout(set = 0, binding = NC_BINDING(sky_specular), rgba16f) uniform writeonly imageCube level_written;
layout(push_constant) uniform SkyCubeConstants { NC_BLOCK_MEMBERS(NC_SKY_CUBE_CONSTANTS_FIELDS) };

#include "../lighting/brdf.glsl"
#include "cube.glsl"

#define PREFILTER_SOURCE(direction, lod) textureLod(sky_cube, direction, lod).rgb
#include "prefilter.glsl"

void main() {
  int size = imageSize(level_written).x;
  ivec3 texel = ivec3(gl_GlobalInvocationID);
  if (texel.x >= size || texel.y >= size) return;
  if (has_atmosphere == 0u) {
    imageStore(level_written, texel, vec4(0.0));
    return;
  }
  vec3 n = cube_texel_direction(uint(texel.z), texel.xy, size);
  if (atmosphere.changed.y == 0u) {
    // The texel's centre through a nearest sampler at this level: the previous frame's texel.
    imageStore(level_written, texel, textureLod(previous_cube, n, float(level)));
    return;
  }
  if (level == 0u) {
    imageStore(level_written, texel, vec4(nearest_half(textureLod(sky_cube, n, 0.0).rgb), 1.0));
    return;
  }
  float roughness = float(level) / float(kSkySpecularMips - 1u);
  vec3 prefiltered = ggx_prefiltered(n, roughness, samples, float(textureSize(sky_cube, 0).x),
                                     float(textureQueryLevels(sky_cube) - 1));
  imageStore(level_written, texel, vec4(nearest_half(prefiltered), 1.0));
}
