// Vertex pulling from scene.geometry and draws.<pass>, shared by every pass that rasterises
// scene geometry. They all place vertices with clip_position(), whose `precise` result forbids
// reassociation and contraction, so the prepass and the G-buffer pass agree bit for bit.
#include "types.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameConstants frame; };
layout(std430, set = 0, binding = 1) readonly buffer VertexBlock { float vertex_data[]; };
layout(std430, set = 0, binding = 2) readonly buffer DrawBlock { Draw draws[]; };


struct SceneVertex {
  vec3 position;
  vec3 normal;
  vec4 tangent;
  vec2 uv0;
  vec2 uv1;
  vec4 color;
};

SceneVertex load_vertex(uint index) {
  uint base = index * VERTEX_FLOATS;
  SceneVertex v;
  v.position = vec3(vertex_data[base], vertex_data[base + 1], vertex_data[base + 2]);
  v.normal = vec3(vertex_data[base + 3], vertex_data[base + 4], vertex_data[base + 5]);
  v.tangent = vec4(vertex_data[base + 6], vertex_data[base + 7], vertex_data[base + 8], vertex_data[base + 9]);
  v.uv0 = vec2(vertex_data[base + 10], vertex_data[base + 11]);
  v.uv1 = vec2(vertex_data[base + 12], vertex_data[base + 13]);
  v.color = vec4(vertex_data[base + 14], vertex_data[base + 15], vertex_data[base + 16], vertex_data[base + 17]);
  return v;
}

vec4 clip_position(Draw draw, vec3 position) {
  precise vec4 world = draw.model * vec4(position, 1.0);
  precise vec4 clip = frame.view_projection * world;
  return clip;
}
