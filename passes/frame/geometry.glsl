// Scene geometry drawn from a view: vertex pulling (vertex_pull.glsl) and the view each draw
// names (views.glsl). clip_position() is `precise` like the decode, so the prepass and the
// G-buffer pass agree bit for bit.
#include "vertex_pull.glsl"

#include "views.glsl"

vec4 clip_position(GpuDraw draw, vec3 position) {
  precise vec4 world = draw.model * vec4(position, 1.0);
  precise vec4 clip = views[draw.view].view_projection * world;
  return clip;
}
