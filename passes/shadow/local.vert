#version 460
// shadow.local and shadow.local_static: a caster's vertex (its draw relative to the spot light)
// in the clip space of the cache slot's map being drawn.
#include "../frame/geometry.glsl"

layout(std140, set = 0, binding = 3) uniform ViewBlock {
  vec4 view_x[16], view_y[16], view_z[16], view_w[16];  // rows of light-relative world → clip, per slot
};

layout(push_constant) uniform Params { uint slot; };

void main() {
  GpuDraw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = vec4(dot(view_x[slot], world), dot(view_y[slot], world), dot(view_z[slot], world),
                     dot(view_w[slot], world));
}
