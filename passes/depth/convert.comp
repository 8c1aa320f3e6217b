#version 460
// depth.convert: one invocation per half-resolution texel converts its 2×2 footprint of the
// device depth to depth.linear and picks the footprint's nearest texel for depth.half and
// stencil.half. Full sizes that are odd clamp the footprint: the last half column (row) covers
// one full column (row), so every full texel is converted exactly once.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "convert.glsl.h"

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
  ivec2 first = 2 * half_texel, last = min(first + 1, full_size - 1);
  // The nearest texel has the largest reversed-Z device depth; ties keep the first in row order,
  // so the choice depends on the input alone (the CPU reference makes the same one).
  ivec2 nearest = first;
  float nearest_device = -1.0, nearest_linear = sky_depth;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      ivec2 p = ivec2(x, y);
      float device = texelFetch(depth_map, p, 0).r;
      float linear = linear_of(device);
      imageStore(linear_depth, p, vec4(linear));
      if (device > nearest_device) {
        nearest = p;
        nearest_device = device;
        nearest_linear = linear;
      }
    }
  // Metres fit a half up to 65504 m (2⁻¹¹ relative); sky and anything farther clamp there.
  imageStore(half_depth, half_texel, vec4(nearest_half(vec3(nearest_linear)).x));
  imageStore(half_stencil, half_texel, uvec4(texelFetch(stencil_map, nearest, 0).r));
}
