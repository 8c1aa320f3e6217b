#version 460
#include "../frame/geometry.glsl"

void main() {
  Draw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  gl_Position = frame.view_projection * (draw.model * vec4(v.position, 1.0));
}
