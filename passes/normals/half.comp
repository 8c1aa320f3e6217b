#version 460
// normals.half: one invocation per half-resolution texel copies the packed normal and the motion
// of the footprint's nearest texel, the texel depth.convert took depth.half from.
#include "half.glsl.h"
#include "../depth/half_footprint.glsl"

layout(local_size_x = kNormalsHalfGroupSide, local_size_y = kNormalsHalfGroupSide) in;

layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
layout(set = 0, binding = NC_BINDING(normals_packed)) uniform sampler2D packed_normals;
layout(set = 0, binding = NC_BINDING(gbuffer_motion)) uniform sampler2D motion_map;
layout(set = 0, binding = NC_BINDING(normals_half), rgba8) uniform writeonly image2D half_normals;
layout(set = 0, binding = NC_BINDING(motion_half), rg16f) uniform writeonly image2D half_motion;

void main() {
  ivec2 half_texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(half_texel, imageSize(half_normals)))) return;
  ivec2 source = half_source_texel(depth_map, half_texel);
  // Copies: an 8-bit code and a half read as floats store back as the same bits.
  imageStore(half_normals, half_texel, texelFetch(packed_normals, source, 0));
  imageStore(half_motion, half_texel, texelFetch(motion_map, source, 0));
}
