#version 460
// decals.normal_copy: texel for texel. A 10-bit (and 2-bit) UNORM code loaded as code / 1023 and
// stored back rounds to the same code, so the copy is exact; gbuffer.normal is only read.
#include "normal_copy.glsl.h"

layout(local_size_x = kNormalCopyGroupSide, local_size_y = kNormalCopyGroupSide) in;

layout(set = 0, binding = NC_BINDING(gbuffer_normal), rgb10_a2) uniform readonly image2D normal;
layout(set = 0, binding = NC_BINDING(decals_normal_copy), rgb10_a2) uniform writeonly image2D normal_copy;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, imageSize(normal_copy)))) return;
  imageStore(normal_copy, texel, imageLoad(normal, texel));
}
