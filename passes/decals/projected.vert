#version 460
// decals.projected: the unit cube of decal gl_InstanceIndex, 6 faces × 2 triangles, each face
// counter-clockwise seen from outside (the pipeline culls front faces: the back faces are drawn).
#include "../frame/types.glsl"

#include "../frame/camera.glsl"
layout(std430, set = 0, binding = NC_BINDING(draws_decals_projected)) readonly buffer DecalBlock { GpuDecal decals[]; };

layout(location = 0) flat out uint out_decal;

const int kCorner[6] = int[6](0, 1, 2, 0, 2, 3);

void main() {
  GpuDecal decal = decals[gl_InstanceIndex];
  int face = gl_VertexIndex / 6, axis = face / 2;
  vec3 n = vec3(0.0);
  n[axis] = (face & 1) != 0 ? 1.0 : -1.0;
  // Two in-plane axes with u × v = n.
  vec3 u = vec3(0.0), v = vec3(0.0);
  u[axis == 0 ? 2 : 0] = 1.0;
  v[axis == 1 ? 2 : 1] = 1.0;
  if (dot(cross(u, v), n) < 0.0) u = -u;
  // A mirroring transform turns the winding: wind the other way in the cube, so faces stay
  // counter-clockwise seen from outside once transformed.
  if (decal.info.z != 0u) u = -u;
  int corner = kCorner[gl_VertexIndex % 6];
  float su = corner == 1 || corner == 2 ? 1.0 : -1.0, sv = corner >= 2 ? 1.0 : -1.0;
  vec3 local = 0.5 * (n + su * u + sv * v);
  gl_Position = camera.view_projection * (decal.model * vec4(local, 1.0));
  out_decal = gl_InstanceIndex;
}
