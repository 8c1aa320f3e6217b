#version 460
#include "tonemap.glsl"

layout(location = 0) flat in vec4 uniform_ldr;
layout(location = 0) out vec4 out_ldr;

void main() {
  if (uniform_inputs)
    out_ldr = uniform_ldr;
  else
    out_ldr = display(ivec2(gl_FragCoord.xy), gl_FragCoord.xy / vec2(textureSize(lit_map, 0)));
}
