#version 460
// shadow.sun_resolve: the sun's visibility at each pixel from shadow.cascades. The cascade is
// chosen by the pixel's view depth (interval-based selection [004 §2.2]), unless a tile its
// filter reads there is not complete (shadow.cull refreshes the static layers a few tiles a
// frame): then the next cascade that holds the filter's texels, with a texel to spare, and whose
// tiles there are complete. Beyond the last split, or with no such cascade, the pixel falls back
// to shadow.distant: the finest level whose map holds the filter's texels around it (none:
// unshadowed), with the same filter and biases. Visibility is the share
// of a (2·FILTER_RADIUS + 1)² block of texels around the pixel's light-space point whose stored
// depth is not nearer the sun than the receiver. The receiver's depth is carried to each texel's
// centre along its own plane (from gbuffer.normal): a receiver-plane bias, so a plane lit at a
// grazing angle does not shadow itself at the texels it slopes away from, and only depth_bias
// texels of constant bias are needed, which keeps the shadow's gap at a contact small. A texel
// at 1 holds no caster: lit, even for a receiver past the map's far depth. R: visibility; G: 1
// (free, frame.md).
#include "../frame/types.glsl"
#include "shadow_layout.glsl.h"
#include "sun_resolve.glsl.h"
#include "sun_filter.glsl"

layout(local_size_x = kSunResolveGroupSide, local_size_y = kSunResolveGroupSide) in;
layout(constant_id = 0) const int FILTER_RADIUS = 1;
// 0 when every cascade's every tile is complete (shadow.sun_resolve.cpp reads shadow.cull_stats):
// the search for a cascade that holds a pixel is then compiled out.
layout(constant_id = 1) const int CHECK_TILES = 1;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std140, set = 0, binding = NC_BINDING(shadow_cascade_data)) uniform CascadeBlock { GpuShadowCascades cascades; };
layout(set = 0, binding = NC_BINDING(scene_depth)) uniform sampler2D depth_map;
layout(set = 0, binding = NC_BINDING(gbuffer_normal)) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(shadow_cascades)) uniform sampler2DArray cascade_maps;
layout(std140, set = 0, binding = NC_BINDING(shadow_distant_data)) uniform DistantBlock { GpuDistantLevels distant; };
layout(set = 0, binding = NC_BINDING(shadow_distant)) uniform sampler2DArray distant_maps;
layout(set = 0, binding = NC_BINDING(shadow_sun), rg8) uniform writeonly image2D sun_out;

layout(push_constant) uniform ResolveConstants { NC_BLOCK_MEMBERS(NC_SUN_RESOLVE_CONSTANTS_FIELDS) };

const int kSide = 2 * FILTER_RADIUS + 1;

// Whether every tile of cascade k is complete (a still camera, or a refresh that kept up).
bool cascade_complete(uint k) {
  uvec4 tiles = cascades.tiles[k];
  int count = int(tiles.z * tiles.z);
  uvec2 every = uvec2(count >= 32 ? ~0u : (1u << count) - 1u,
                      count >= 64 ? ~0u : count > 32 ? (1u << (count - 32)) - 1u : 0u);
  return tiles.xy == every;
}

// Whether cascade k can shadow the point: every tile holding a texel its filter reads is complete
// and, when k is not the pixel's own cascade, those texels lie inside the map with one to spare.
bool cascade_holds(int k, vec3 position, bool own) {
  uvec4 tiles = cascades.tiles[k];
  int resolution = int(cascades.light_direction.w);
  vec2 clip = (cascades.light_from_world[k] * vec4(position, 1.0)).xy;
  ivec2 base = ivec2(floor((clip * 0.5 + 0.5) * float(resolution)));
  ivec2 lo = base - FILTER_RADIUS, hi = base + FILTER_RADIUS;
  if (!own && (any(lessThan(lo, ivec2(1))) || any(greaterThan(hi, ivec2(resolution - 2))))) return false;
  int side = resolution / int(tiles.z);
  ivec2 first = clamp(lo, ivec2(0), ivec2(resolution - 1)) / side, last = clamp(hi, ivec2(0), ivec2(resolution - 1)) / side;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      int bit = y * int(tiles.z) + x;
      uint word = bit < 32 ? tiles.x : tiles.y;
      if ((word >> uint(bit & 31) & 1u) == 0u) return false;
    }
  return true;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(camera.viewport.xy)))) return;
  float depth = texelFetch(depth_map, pixel, 0).r;
  vec2 ndc = (vec2(pixel) + 0.5) * camera.viewport.zw * 2.0 - 1.0;
  vec4 p = camera.inverse_view_projection * vec4(ndc, max(depth, 1e-30), 1.0);
  vec3 position = p.xyz / p.w;  // camera-relative world, as lighting.tiled finds it
  float view_depth = camera.projection_params.x / max(depth, 1e-30);
  uint cascade = (view_depth > cascades.splits.x ? 1u : 0u) + (view_depth > cascades.splits.y ? 1u : 0u) +
                 (view_depth > cascades.splits.z ? 1u : 0u);
  vec3 n = texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0;
  n = dot(n, n) > 1e-8 ? normalize(n) : vec3(0.0);
  // Beyond the last split: the finest distant level that holds every texel the filter reads,
  // with a texel to spare (4: none, unshadowed).
  float distant_resolution = distant.light_direction.w;
  int level = distant_level(distant, position, FILTER_RADIUS);
  // The pixel's own cascade when it is complete; else a search that only the pixels needing it
  // enter (a loop, which lavapipe runs once when no lane of a row enters it; an if it would run
  // whole), and that is not compiled at all when every cascade is complete.
  bool in_range = depth > 0.0 && view_depth <= cascades.splits.w;
  int chosen = in_range && (CHECK_TILES == 0 || cascade_complete(cascade)) ? int(cascade) : 4;
  if (CHECK_TILES != 0)
    for (int k = in_range && chosen == 4 ? int(cascade) : 4; k < 4 && chosen == 4; ++k)
      if (cascade_holds(k, position, k == int(cascade))) chosen = k;
  bool in_cascades = chosen < 4;
  bool in_distant = depth > 0.0 && !in_cascades && level < 4;
  ShadowMap map;
  if (in_distant) {
    map = ShadowMap(level, distant.light_from_world[level], distant.texel_metres[level], distant.depth_metres[level],
                    distant_resolution);
  } else {
    int k = min(chosen, 3);
    map = ShadowMap(k, cascades.light_from_world[k], cascades.texel_metres[k], cascades.depth_metres[k],
                    cascades.light_direction.w);
  }
  Receiver r = receiver_in(map, position, n, max_slope, depth_bias);
  int last = int(map.resolution) - 1;
  // One loop per kind of map, run for the pixels that read it (lit_taps): a row of cascade pixels
  // does not pay for the distant levels' taps, nor a row of sky for either.
  float lit = lit_taps(cascade_maps, map.layer, r, FILTER_RADIUS, last, in_cascades ? kSide * kSide : 0) +
              lit_taps(distant_maps, map.layer, r, FILTER_RADIUS, last, in_distant ? kSide * kSide : 0);
  float visibility = in_cascades || in_distant ? lit / float(kSide * kSide) : 1.0;
  imageStore(sun_out, pixel, vec4(visibility, 1.0, 0.0, 0.0));
}
