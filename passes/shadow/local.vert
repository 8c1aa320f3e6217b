#version 460
// shadow.local: a caster's vertex in the clip space of the spot light's map being drawn.
#include "../frame/geometry.glsl"

layout(std140, set = 0, binding = 3) uniform LocalBlock {
  vec4 clip_x[16], clip_y[16], clip_z[16], clip_w[16];  // rows of camera-relative world → clip
  vec4 depth_range[16];
  uvec4 counts;
};

layout(push_constant) uniform Params { uint slice; };

void main() {
  Draw draw = draws[gl_InstanceIndex];
  SceneVertex v = load_vertex(gl_VertexIndex);
  precise vec4 world = draw.model * vec4(v.position, 1.0);
  gl_Position = vec4(dot(clip_x[slice], world), dot(clip_y[slice], world), dot(clip_z[slice], world),
                     dot(clip_w[slice], world));
}
