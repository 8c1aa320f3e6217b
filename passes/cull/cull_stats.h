// cull.stats: what cull.main did this frame, recorded with the frame (and printed by the
// benchmark). cull.occlusion, its occlusion buffer: passes/frame/occlusion_buffer.h.
#pragma once

#include <cstdint>

#include "passes/core/buffer_schema.h"

namespace nightcap {

constexpr uint32_t kLodBins = 4;  // levels 0, 1, 2 and 3 or coarser

struct CullStats {
  uint32_t instances_tested;   // every instance looked at, culled whole with a node or alone
  uint32_t culled_frustum;     // outside the view frustum (kept when frustum=0)
  uint32_t culled_occlusion;   // hidden behind the occluders (kept when occlusion=0)
  uint32_t culled_degenerate;  // zero or non-finite scale, an empty mesh or an unknown material
  uint32_t culled_distance;    // beyond its mesh's draw distance (a level of detail, not visibility)
  uint32_t visible;            // drawn and inside the frustum
  uint32_t occluders, occluder_triangles;
  uint32_t draws_prepass, draws_gbuffer, draws_dynamic;  // instanced draw calls issued
  uint32_t triangles_prepass, triangles_gbuffer, triangles_dynamic;
  uint32_t lod_histogram[kLodBins];  // visible instances per level of detail
  uint32_t decals_mesh;              // mesh decal instances drawn (draws.decals.mesh)
  uint32_t decals_projected;         // projected decals drawn (draws.decals.projected)
};
static_assert(sizeof(CullStats) == 80);

inline BufferSchema cull_stats_schema() {
  using S = CullStats;
  return BufferSchema::of<S>()
      .field("instances_tested", &S::instances_tested)
      .field("culled_frustum", &S::culled_frustum)
      .field("culled_occlusion", &S::culled_occlusion)
      .field("culled_degenerate", &S::culled_degenerate)
      .field("culled_distance", &S::culled_distance)
      .field("visible", &S::visible)
      .field("occluders", &S::occluders)
      .field("occluder_triangles", &S::occluder_triangles)
      .field("draws_prepass", &S::draws_prepass)
      .field("draws_gbuffer", &S::draws_gbuffer)
      .field("draws_dynamic", &S::draws_dynamic)
      .field("triangles_prepass", &S::triangles_prepass)
      .field("triangles_gbuffer", &S::triangles_gbuffer)
      .field("triangles_dynamic", &S::triangles_dynamic)
      .field("lod_histogram", &S::lod_histogram)
      .field("decals_mesh", &S::decals_mesh)
      .field("decals_projected", &S::decals_projected);
}

}  // namespace nightcap
