#version 460
// decals.mesh: a decal surface over the G-buffer (see mesh.cpp for the blend). Its opacity is
// the base colour's alpha; its normal is the mesh's, turned by the material's normal map where
// the mesh has tangents.
#include "../frame/types.glsl"

layout(std430, set = 0, binding = NC_BINDING(draws)) readonly buffer DrawBlock { GpuDraw draws[]; };
layout(std430, set = 0, binding = NC_BINDING(scene_materials)) readonly buffer MaterialBlock { GpuMaterial materials[]; };
layout(set = 0, binding = NC_BINDING(scene_texture)) uniform sampler2D base_color_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 1) uniform sampler2D metallic_roughness_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 2) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(decals_normal_copy)) uniform sampler2D normal_copy;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec4 in_color;
layout(location = 5) flat in uint in_draw;

layout(location = 0) out vec4 out_albedo;    // rgb blended by a; alpha masked (object flags kept)
layout(location = 1) out vec4 out_normal;    // the blended normal, 0.5n+0.5, weight 1; alpha masked
layout(location = 2) out vec4 out_material;  // metalness, roughness, translucency blended by a; alpha masked

vec2 slot_uv(GpuMaterial m, int slot) {
  return ((m.textures2.y >> slot) & 1) != 0 ? in_uv.zw : in_uv.xy;
}

void main() {
  GpuMaterial m = materials[draws[in_draw].material];
  vec4 base = m.base_color * in_color;
  if (m.textures.x >= 0) base *= texture(base_color_map, slot_uv(m, 0));
  float a = clamp(base.a, 0.0, 1.0);
  if (!(a > 0.0)) discard;  // transparent: every target stays as it was

  float metallic = m.pbr.x, roughness = m.pbr.y;
  if (m.textures.y >= 0) {
    vec4 mr = texture(metallic_roughness_map, slot_uv(m, 1));
    roughness *= mr.g;
    metallic *= mr.b;
  }

  vec3 n = dot(in_normal, in_normal) > 1e-20 ? normalize(in_normal)
                                              : normalize(cross(dFdx(in_position), dFdy(in_position)));
  if (any(isnan(n))) n = vec3(0.0, 0.0, 1.0);
  if (m.textures.z >= 0 && dot(in_tangent.xyz, in_tangent.xyz) > 0.0) {
    vec3 t = normalize(in_tangent.xyz - n * dot(n, in_tangent.xyz));
    vec3 b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
    vec3 tn = texture(normal_map, slot_uv(m, 2)).xyz * 2.0 - 1.0;
    tn.xy *= m.pbr.w;
    vec3 mapped = t * tn.x + b * tn.y + n * tn.z;
    if (dot(mapped, mapped) > 1e-12) n = normalize(mapped);
  }
  if (!gl_FrontFacing) n = -n;

  // The custom blend: the surface's normal from the copy, pulled toward the decal's by a. Two
  // opposite normals blended half and half cancel: the decal's is kept there.
  vec3 surface = texelFetch(normal_copy, ivec2(gl_FragCoord.xy), 0).xyz * 2.0 - 1.0;
  vec3 blended = (1.0 - a) * surface + a * n;
  n = dot(blended, blended) > 1e-12 ? normalize(blended) : n;

  out_albedo = vec4(clamp(base.rgb, 0.0, 1.0), a);
  out_normal = vec4(n * 0.5 + 0.5, 1.0);  // blended with weight 1: written as it is
  out_material = vec4(clamp(metallic, 0.0, 1.0), clamp(roughness, 0.0, 1.0), 0.0, a);
}
