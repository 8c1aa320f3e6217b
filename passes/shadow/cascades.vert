#version 460
// shadow.cascades: a caster's vertex in the light clip space of the cascade being drawn.
#include "../frame/vertex_pull.glsl"
#include "caster_draw.glsl.h"
#include "shadow_layout.glsl.h"

layout(std140, set = 0, binding = NC_BINDING(shadow_cascade_data)) uniform CascadeBlock { GpuShadowCascades cascades; };

layout(push_constant) uniform CasterConstants { NC_BLOCK_MEMBERS(NC_CASTER_CONSTANTS_FIELDS) };

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = cascades.light_from_world[layer] * world;
}
