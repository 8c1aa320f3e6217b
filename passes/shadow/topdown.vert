#version 460
// shadow.topdown: a static caster's vertex in the top-down map's clip space.
#include "../frame/vertex_pull.glsl"
#include "caster_draw.glsl.h"
#include "topdown_layout.glsl.h"

layout(std140, set = 0, binding = NC_BINDING(shadow_topdown_data)) uniform TopdownBlock { GpuTopdown topdown; };

layout(push_constant) uniform CasterConstants { NC_BLOCK_MEMBERS(NC_CASTER_CONSTANTS_FIELDS) };

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = topdown.map_from_world * world;
}
