// What the sun's shadow passes hand each other: shadow.cull (CPU) writes the cascades'
// projections (shadow.cascade_data, read by shadow.cascades and shadow.sun_resolve), one draw
// list per cascade packed into draws.shadow.cascades, and what it culled (shadow.cull_stats).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "passes/core/buffer_schema.h"

namespace nightcap {

constexpr uint32_t kShadowCascades = 4;
// Texels per side of each cascade by default (shadow.cull.resolution and shadow.cascades.resolution,
// which must agree: shadow.cascades checks).
constexpr uint32_t kShadowResolution = 1024;

// Mirrored by passes/shadow/cascades.vert and sun_resolve.comp (std140).
struct GpuShadowCascades {
  // Camera-relative world → the cascade's light clip space: x and y in [-1, 1] across the map,
  // z in [0, 1] from the light's near plane (the scene's side nearest the sun) to its far one.
  glm::mat4 light_from_world[kShadowCascades];
  glm::vec4 splits;           // view depth (metres along the view axis) where each cascade ends
  glm::vec4 texel_metres;     // a texel's side in metres, per cascade
  glm::vec4 depth_metres;     // metres of light depth that z's [0, 1] spans, per cascade
  glm::vec4 light_direction;  // xyz: the way sunlight travels; w: the map's resolution in texels
};
static_assert(sizeof(GpuShadowCascades) == 4 * 64 + 4 * 16);

struct ShadowCullStats {
  uint32_t casters_tested[kShadowCascades];  // opaque instances looked at, and every instance of a culled node
  uint32_t casters_culled[kShadowCascades];  // outside the cascade's volume (kept when culling=0)
  uint32_t casters_hidden[kShadowCascades];  // inside it, but their shadow hidden from the view (kept when culling=0)
  uint32_t draws[kShadowCascades];           // records of draws.shadow.cascades for each cascade
  uint32_t first_draw[kShadowCascades];      // where each cascade's records start
  uint32_t triangles[kShadowCascades];
  uint32_t planes[kShadowCascades];  // planes of the culling volume (at most 8)
  // Casters that passed the tests above but scene.tod (`render --tod`) says cast no visible
  // shadow at this hour, and the triangles they would have drawn.
  uint32_t casters_tod_dropped[kShadowCascades];
  uint32_t tod_triangles_saved[kShadowCascades];
};
static_assert(sizeof(ShadowCullStats) == 9 * 16);

inline BufferSchema shadow_cascades_schema() {
  using S = GpuShadowCascades;
  return BufferSchema::of<S>()
      .field("light_from_world", &S::light_from_world)
      .field("splits", &S::splits)
      .field("texel_metres", &S::texel_metres)
      .field("depth_metres", &S::depth_metres)
      .field("light_direction", &S::light_direction);
}

inline BufferSchema shadow_cull_stats_schema() {
  using S = ShadowCullStats;
  return BufferSchema::of<S>()
      .field("casters_tested", &S::casters_tested)
      .field("casters_culled", &S::casters_culled)
      .field("casters_hidden", &S::casters_hidden)
      .field("draws", &S::draws)
      .field("first_draw", &S::first_draw)
      .field("triangles", &S::triangles)
      .field("planes", &S::planes)
      .field("casters_tod_dropped", &S::casters_tod_dropped)
      .field("tod_triangles_saved", &S::tod_triangles_saved);
}

}  // namespace nightcap
