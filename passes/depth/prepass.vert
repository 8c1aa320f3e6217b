#version 460
#include "../frame/geometry.glsl"

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  gl_Position = clip_position(draw, v.position);
}
