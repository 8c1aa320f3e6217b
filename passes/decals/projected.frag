#version 460
// decals.projected: the surface under this pixel, if it lies inside the decal's box and is not
// tagged moving, takes the decal's pattern (see projected.cpp for the blend).
#include "../frame/types.glsl"

#include "../frame/camera.glsl"
layout(std430, set = 0, binding = NC_BINDING(draws_decals_projected)) readonly buffer DecalBlock { GpuDecal decals[]; };
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
layout(set = 0, binding = NC_BINDING(scene_depth) + 1) uniform usampler2D stencil_map;

layout(location = 0) flat in uint in_decal;

layout(location = 0) out vec4 out_albedo;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_material;

const uint STENCIL_MOVING = 0x02u;
// DecalPattern (passes/scene/scene.h).
const uint PATTERN_SOLID = 0u, PATTERN_STRIPES = 1u, PATTERN_GRIME = 2u, PATTERN_COORDINATES = 3u;

// A value in [0, 1) per integer cell (a 32-bit integer hash, the same on every device).
float cell_value(ivec2 cell, uint seed) {
  uint h = uint(cell.x) * 0x8da6b343u ^ uint(cell.y) * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  return float(h >> 8) * (1.0 / 16777216.0);
}

// Bilinear value noise over cells of size 1.
float value_noise(vec2 p, uint seed) {
  vec2 f = fract(p);
  ivec2 c = ivec2(floor(p));
  vec2 s = f * f * (3.0 - 2.0 * f);
  float a = cell_value(c, seed), b = cell_value(c + ivec2(1, 0), seed);
  float d = cell_value(c + ivec2(0, 1), seed), e = cell_value(c + ivec2(1, 1), seed);
  return mix(mix(a, b, s.x), mix(d, e, s.x), s.y);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(depth_map, pixel, 0).r;
  if (!(depth > 0.0)) discard;  // sky
  if ((texelFetch(stencil_map, pixel, 0).r & STENCIL_MOVING) != 0u) discard;

  vec2 ndc = (vec2(pixel) + 0.5) * camera.viewport.zw * 2.0 - 1.0;
  vec4 p = camera.inverse_view_projection * vec4(ndc, depth, 1.0);
  GpuDecal decal = decals[in_decal];
  vec3 local = (decal.local_from_world * vec4(p.xyz / p.w, 1.0)).xyz;
  // Outside the unit cube (a NaN fails the test too).
  if (!all(lessThanEqual(abs(local), vec3(0.5)))) discard;

  vec3 albedo = decal.albedo.rgb;
  float a = decal.albedo.a;
  uint pattern = decal.info.x;
  float scale = decal.surface.w;
  if (pattern == PATTERN_STRIPES) {
    // Dashes along u, as long as the gaps between them.
    a *= fract((local.x + 0.5) * scale) < 0.5 ? 1.0 : 0.0;
  } else if (pattern == PATTERN_GRIME) {
    float n = 0.65 * value_noise((local.xy + 0.5) * scale, decal.info.y) +
              0.35 * value_noise((local.xy + 0.5) * scale * 3.0, decal.info.y + 1u);
    // Fading toward the sides of the box, so the grime has no hard edge.
    vec2 edge = clamp((0.5 - abs(local.xy)) * 5.0, 0.0, 1.0);
    a *= smoothstep(0.35, 0.75, n) * edge.x * edge.y;
  } else if (pattern == PATTERN_COORDINATES) {
    albedo = local + 0.5;
  }
  if (!(a > 0.0)) discard;  // nothing to blend: the targets keep their values

  out_albedo = vec4(clamp(albedo, 0.0, 1.0), a);
  out_normal = vec4(decal.facing.xyz * 0.5 + 0.5, a * decal.surface.z);
  out_material = vec4(decal.surface.x, decal.surface.y, 0.0, a);
}
