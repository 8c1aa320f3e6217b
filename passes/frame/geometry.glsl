// Vertex pulling from scene.geometry and draws.<pass>, shared by every pass that rasterises
// scene geometry. They all decode positions in the draw's box and place vertices with
// clip_position(), both `precise` (no reassociation or contraction), so the prepass and the
// G-buffer pass agree bit for bit.
#include "types.glsl"

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(std430, set = 0, binding = NC_BINDING(scene_geometry)) readonly buffer GeometryBlock { uint geometry_words[]; };
layout(std430, set = 0, binding = NC_BINDING(draws)) readonly buffer DrawBlock { GpuDraw draws[]; };
#include "vertex_streams.glsl"

// Vertex `index` of scene.geometry, its position in the box of the draw being drawn.
SceneVertex load_vertex(uint index) {
  GpuDraw draw = draws[gl_InstanceIndex];
  return decode_vertex(index, draw.position_origin.xyz, draw.position_step.xyz);
}

vec4 clip_position(GpuDraw draw, vec3 position) {
  precise vec4 world = draw.model * vec4(position, 1.0);
  precise vec4 clip = frame.view_projection * world;
  return clip;
}
