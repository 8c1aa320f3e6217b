#version 460
// shadow.local and shadow.local_static: a caster's vertex (its draw relative to the spot light)
// in the clip space of the cache slot's map being drawn.
#include "../frame/vertex_pull.glsl"
#include "caster_draw.glsl.h"
#include "local_layout.glsl.h"

layout(std140, set = 0, binding = NC_BINDING(shadow_local_views)) uniform ViewBlock { GpuLocalShadowViews views; };

layout(push_constant) uniform CasterConstants { NC_BLOCK_MEMBERS(NC_CASTER_CONSTANTS_FIELDS) };

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = vec4(dot(views.view_x[layer], world), dot(views.view_y[layer], world), dot(views.view_z[layer], world),
                     dot(views.view_w[layer], world));
}
