#version 460
// shadow.distant: a static caster's vertex in the light clip space of the level being drawn.
#include "../frame/vertex_pull.glsl"
#include "caster_draw.glsl.h"
#include "shadow_layout.glsl.h"

layout(std140, set = 0, binding = NC_BINDING(shadow_distant_data)) uniform DistantBlock { GpuDistantLevels levels; };

layout(push_constant) uniform CasterConstants { NC_BLOCK_MEMBERS(NC_CASTER_CONSTANTS_FIELDS) };

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = levels.light_from_world[layer] * world;
}
