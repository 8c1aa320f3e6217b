#version 460
// ao.filter: one invocation per half-resolution texel averages ao.raw over a square window of
// its neighbours, each weighted by how near it lies to the texel's tangent plane (a fraction of
// the texel's depth) and by how close its normal is to the texel's: the interleaved noise of
// ao.gtao's slices averages out across the window, and no occlusion crosses to another surface.
// The bent normals are averaged with the same weights and renormalised. A workgroup first loads
// the view-space points, normals and values of its tile and an apron of the largest radius once.
#include "../depth/half_footprint.glsl"
#include "../frame/types.glsl"
#include "filter.glsl.h"

layout(local_size_x = kAoFilterGroupSide, local_size_y = kAoFilterGroupSide) in;
const int SIDE = int(kAoFilterGroupSide), APRON = kAoFilterMaxRadius, SPAN = SIDE + 2 * APRON;

#include "../frame/camera.glsl"
#include "half_view.glsl"
layout(set = 0, binding = NC_BINDING(ao_raw)) uniform sampler2D raw;
layout(set = 0, binding = NC_BINDING(depth_half)) uniform sampler2D half_depth;
layout(set = 0, binding = NC_BINDING(normals_half)) uniform sampler2D half_normals;
layout(set = 0, binding = NC_BINDING(ao_filtered), rgba8) uniform writeonly image2D filtered;
layout(push_constant) uniform AoFilterConstants { NC_BLOCK_MEMBERS(NC_AO_FILTER_CONSTANTS_FIELDS) };

shared vec4 tile_point[SPAN * SPAN];   // view-space point; w 1 where something was drawn, else 0
shared vec3 tile_normal[SPAN * SPAN];  // world-space unit normal
shared vec4 tile_value[SPAN * SPAN];   // ao.raw

void main() {
  ivec2 size = textureSize(half_depth, 0);
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * SIDE - APRON;
  for (int i = int(gl_LocalInvocationIndex); i < SPAN * SPAN; i += SIDE * SIDE) {
    ivec2 at = origin + ivec2(i % SPAN, i / SPAN);
    tile_point[i] = vec4(0.0);
    if (any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, size))) continue;
    float depth = texelFetch(half_depth, at, 0).r;
    vec3 stored = stored_vector(texelFetch(half_normals, at, 0));
    tile_value[i] = texelFetch(raw, at, 0);
    if (!drawn(depth) || !is_vector(stored)) continue;
    tile_point[i] = vec4(view_point(footprint_centre(at), depth), 1.0);
    tile_normal[i] = normalize(stored);
  }
  barrier();
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size))) return;
  ivec2 local = ivec2(gl_LocalInvocationID.xy) + APRON;
  int own = local.y * SPAN + local.x;
  // Nothing drawn: ao.gtao stored the clear value, which is kept.
  if (tile_point[own].w == 0.0) {
    imageStore(filtered, texel, tile_value[own]);
    return;
  }
  vec3 normal = tile_normal[own];
  vec3 view_normal = mat3(camera.view) * normal;
  vec3 point = tile_point[own].xyz;
  float tolerance = plane_tolerance * -point.z;

  float weights = 0.0, visibility = 0.0;
  vec3 bent = vec3(0.0);
  for (int y = -radius; y <= radius; ++y)
    for (int x = -radius; x <= radius; ++x) {
      int at = (local.y + y) * SPAN + local.x + x;
      if (tile_point[at].w == 0.0) continue;  // nothing drawn, or outside the image
      float plane_weight = clamp(1.0 - abs(dot(view_normal, tile_point[at].xyz - point)) / tolerance, 0.0, 1.0);
      float weight = plane_weight * pow(max(dot(normal, tile_normal[at]), 0.0), normal_power);
      weights += weight;
      visibility += weight * tile_value[at].a;
      bent += weight * stored_vector(tile_value[at]);
    }
  // The texel itself weighs 1 (its normal quantised to 8 bits, nearly so): `weights` is not 0.
  visibility /= max(weights, 1e-6);
  imageStore(filtered, texel, vec4((is_vector(bent) ? normalize(bent) : normal) * 0.5 + 0.5, visibility));
}
