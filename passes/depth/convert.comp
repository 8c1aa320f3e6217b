#version 460
// depth.convert: one invocation per half-resolution texel converts its footprint of the device
// depth to depth.linear and takes depth.half and stencil.half from the footprint's nearest texel
// (half_footprint.glsl). Every full texel is in exactly one footprint, so it is converted once.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "convert.glsl.h"
#include "half_footprint.glsl"

layout(local_size_x = kDepthConvertGroupSide, local_size_y = kDepthConvertGroupSide) in;

#include "../frame/camera.glsl"
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
layout(set = 0, binding = NC_BINDING(scene_depth) + 1) uniform usampler2D stencil_map;
layout(set = 0, binding = NC_BINDING(depth_linear), r32f) uniform writeonly image2D linear_depth;
layout(set = 0, binding = NC_BINDING(depth_half), r16f) uniform writeonly image2D half_depth;
layout(set = 0, binding = NC_BINDING(stencil_half), r8ui) uniform writeonly uimage2D half_stencil;
layout(push_constant) uniform DepthConvertConstants { NC_BLOCK_MEMBERS(NC_DEPTH_CONVERT_CONSTANTS_FIELDS) };

float linear_of(float device) {
  // Reversed-Z with an infinite far plane: device = znear / distance, so the division is exact
  // to one rounding; 0 (nothing drawn) maps to a finite stand-in for infinity.
  return device > 0.0 ? min(camera.projection_params.x / device, sky_depth) : sky_depth;
}

void main() {
  ivec2 half_texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 full_size = textureSize(depth_map, 0);
  if (any(greaterThanEqual(half_texel, (full_size + 1) / 2))) return;
  ivec2 first, last;
  half_footprint(half_texel, full_size, first, last);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x)
      imageStore(linear_depth, ivec2(x, y), vec4(linear_of(texelFetch(depth_map, ivec2(x, y), 0).r)));
  ivec2 nearest = half_source_texel(depth_map, half_texel);
  // Metres fit a half up to 65504 m (2⁻¹¹ relative); sky and anything farther clamp there.
  float nearest_linear = linear_of(texelFetch(depth_map, nearest, 0).r);
  imageStore(half_depth, half_texel, vec4(nearest_half(vec3(nearest_linear)).x));
  imageStore(half_stencil, half_texel, uvec4(texelFetch(stencil_map, nearest, 0).r));
}
