#version 460
// sky.cubemap, one level per dispatch. Level 0: sky.view's radiance along each texel's direction
// (the sky as the composite draws it; the light's own disk is not in it: direct light lights
// that), made finite and kept within B10G11R11's range. Each later level: the mean of the 2×2
// texels above it on the same face, the chain sky.specular picks its levels from. Copied from the
// previous frame's when sky.atmosphere says the sky seen from the camera did not change.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "atmosphere.glsl.h"
#include "ibl.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_view)) uniform sampler2D sky_view_lut;
layout(set = 0, binding = NC_BINDING(sky_cubemap_previous)) uniform samplerCube previous_cube;
layout(set = 0, binding = NC_BINDING(sky_cubemap), r11f_g11f_b10f) uniform readonly imageCube level_above;
layout(set = 0, binding = NC_BINDING(sky_cubemap) + 1, r11f_g11f_b10f) uniform writeonly imageCube level_written;
layout(push_constant) uniform SkyCubeConstants { NC_BLOCK_MEMBERS(NC_SKY_CUBE_CONSTANTS_FIELDS) };

#include "atmosphere.glsl"
#include "camera_height.glsl"
#include "cube.glsl"
#include "view_lookup.glsl"

// Within B10G11R11's range and rounded to its nearest value (lavapipe's store truncates: each
// level of the chain would lose up to an ULP more, 3% in blue, half.glsl). NaN (a corrupt
// sky.view) becomes 0 rather than spreading through every mip and every reflection.
vec3 storable(vec3 c) {
  bvec3 finite = not(isnan(c));
  return nearest_b10g11r11(clamp(vec3(finite.x ? c.x : 0.0, finite.y ? c.y : 0.0, finite.z ? c.z : 0.0), 0.0, 64512.0));
}

void main() {
  int size = imageSize(level_written).x;
  ivec3 texel = ivec3(gl_GlobalInvocationID);
  if (texel.x >= size || texel.y >= size) return;
  vec3 radiance = vec3(0.0);
  if (has_atmosphere != 0u && atmosphere.changed.y == 0u) {
    // The texel's centre through a nearest sampler at this level: the previous frame's texel.
    radiance = textureLod(previous_cube, cube_texel_direction(uint(texel.z), texel.xy, size), float(level)).rgb;
  } else if (has_atmosphere != 0u) {
    if (level == 0u) {
      radiance = sky_view_radiance(cube_texel_direction(uint(texel.z), texel.xy, size));
    } else {
      ivec3 first = ivec3(texel.xy * 2, texel.z);
      radiance = 0.25 * (imageLoad(level_above, first).rgb + imageLoad(level_above, first + ivec3(1, 0, 0)).rgb +
                         imageLoad(level_above, first + ivec3(0, 1, 0)).rgb +
                         imageLoad(level_above, first + ivec3(1, 1, 0)).rgb);
    }
  }
  imageStore(level_written, texel, vec4(storable(radiance), 1.0));
}
