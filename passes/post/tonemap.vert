#version 460
// The full-screen triangle, and, when the inputs are uniform, the one display colour of the
// whole output: evaluated here once per vertex, the fragments only copy it.
#include "tonemap.glsl"

layout(location = 0) flat out vec4 uniform_ldr;

void main() {
  vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
  uniform_ldr = uniform_inputs ? display(ivec2(0), 0.5 / vec2(textureSize(lit_map, 0))) : vec4(0.0);
}
