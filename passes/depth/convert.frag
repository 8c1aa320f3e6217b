#version 460
#include "../frame/types.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameConstants frame; };
layout(set = 0, binding = 1) uniform sampler2D depth_map;
layout(push_constant) uniform Params { float sky_depth; };
layout(location = 0) in vec2 in_uv;
layout(location = 0) out float out_linear;

void main() {
  float device = texelFetch(depth_map, ivec2(gl_FragCoord.xy), 0).r;
  // Reversed-Z with an infinite far plane: device = znear / distance, so the division is exact
  // to one rounding; 0 (nothing drawn) maps to a finite stand-in for infinity.
  out_linear = device > 0.0 ? min(frame.projection_params.x / device, sky_depth) : sky_depth;
}
