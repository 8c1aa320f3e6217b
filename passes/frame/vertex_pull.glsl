// Vertex pulling from scene.geometry and draws.<pass>, shared by every pass that rasterises
// scene geometry. They all decode positions in the draw's box, `precise` (no reassociation or
// contraction), so the prepass and the G-buffer pass agree bit for bit.
#include "types.glsl"

layout(std430, set = 0, binding = NC_BINDING(scene_geometry)) readonly buffer GeometryBlock { uint geometry_words[]; };
layout(std430, set = 0, binding = NC_BINDING(draws)) readonly buffer DrawBlock { GpuDraw draws[]; };
#include "vertex_streams.glsl"

// Vertex `index` of scene.geometry, its position in the box of the draw being drawn.
SceneVertex load_vertex(uint index) {
  GpuDraw draw = draws[gl_InstanceIndex];
  return decode_vertex(index, draw.position_origin.xyz, draw.position_step.xyz);
}
