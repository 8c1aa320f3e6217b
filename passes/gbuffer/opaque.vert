#version 460
#include "../frame/geometry.glsl"

layout(location = 0) out vec3 out_position;  // camera-relative world
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) out vec4 out_uv;        // uv0, uv1
layout(location = 4) out vec4 out_color;
layout(location = 5) flat out uint out_draw;

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  gl_Position = clip_position(draw, v.position);
  out_position = (draw.model * vec4(v.position, 1.0)).xyz;
  out_normal = mat3(draw.normal_matrix) * v.normal;
  out_tangent = vec4(mat3(draw.model) * v.tangent.xyz, v.tangent.w);
  out_uv = vec4(v.uv0, v.uv1);
  out_color = v.color;
  out_draw = gl_InstanceIndex;
}
