// What the local-light shadow passes hand each other (frame.md section 1, shadow.local):
// shadow.local_plan (CPU) picks the spot lights that get a map this frame and writes their
// projections (shadow.local_data, read by shadow.local, shadow.local_moments and
// lighting.tiled), which map each light of frame.lights uses (shadow.local_slots), one draw list
// per map packed into draws.shadow.local, and its recorded decision (shadow.local_plan).
#pragma once

#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <span>
#include <string>

#include "passes/core/buffer_schema.h"
#include "passes/core/graph.h"

namespace nightcap {

// Layers of shadow.local and shadow.local_moments: frame.md's 10-20 slices. The plan's max_maps
// uses at most this many.
constexpr uint32_t kLocalShadowSlices = 16;
constexpr uint32_t kLocalShadowResolution = 512;
// The moments' blur radius shadow.local_moments supports at most (its shared-memory tile).
constexpr uint32_t kLocalShadowMaxBlur = 4;

// Mirrored by passes/shadow/local.vert, local_moments.comp and lighting/tiled.comp (std140).
struct GpuLocalShadows {
  // Camera-relative world → the map's clip space, a row of the matrix each (the capture's
  // schema holds arrays of at most 64 numbers): a perspective along the spot's axis, z in [0, 1]
  // (forward) from `near` to the light's range; w is the distance along that axis.
  glm::vec4 clip_x[kLocalShadowSlices], clip_y[kLocalShadowSlices], clip_z[kLocalShadowSlices],
      clip_w[kLocalShadowSlices];
  // Per map: x near, y far (metres along the axis), z 1 / (far − near), w: the light's index in
  // frame.lights.
  glm::vec4 depth_range[kLocalShadowSlices];
  // x: maps this frame; y: moments per texel in shadow.local_moments, 2 (variance shadow maps)
  // or 4 (moment shadow maps), from shadow.local_plan's `moments`; z, w: unused.
  glm::uvec4 counts;
};
static_assert(sizeof(GpuLocalShadows) == kLocalShadowSlices * 80 + 16);

// counts.y of shadow.local_data's bytes: which moments shadow.local_moments writes and
// lighting.tiled reconstructs, each picking its pipeline by it (`pass` names the reader in the error).
inline int32_t local_shadow_moments(std::span<const uint8_t> data, const std::string& pass) {
  GpuLocalShadows shadows;
  if (data.size() < sizeof shadows)
    throw GraphError(pass + ": shadow.local_data has " + std::to_string(data.size()) + " bytes, not " +
                     std::to_string(sizeof shadows));
  std::memcpy(&shadows, data.data(), sizeof shadows);
  if (shadows.counts.y != 2 && shadows.counts.y != 4)
    throw GraphError(pass + ": shadow.local_data says " + std::to_string(shadows.counts.y) +
                     " moments per texel; 2 or 4 are made");
  return int32_t(shadows.counts.y);
}

// Why a spot light has a map this frame or not (LocalShadowPlan::reason).
enum class LocalShadowReason : uint32_t {
  selected = 1,         // among the max_maps largest on screen: refreshed this frame
  over_budget = 2,      // a shadow-casting light in view, but max_maps nearer or larger ones took the maps
  unbounded_range = 3,  // range 0: no far plane for a map
};

// Candidates the record names (the rest are counted): the capture's schema holds arrays of at most 64.
constexpr uint32_t kLocalShadowRecorded = 64;

// What shadow.local_plan decided, as the capture records it.
struct LocalShadowPlan {
  uint32_t candidates;  // spot lights in frame.lights (in view)
  uint32_t maps;        // maps drawn this frame (all refreshed: see local_plan.cpp on caching)
  uint32_t dropped;     // candidates without a map
  uint32_t draws, triangles;
  uint32_t max_maps;
  uint32_t pad[2];
  uint32_t slice_first_draw[kLocalShadowSlices];  // the map's range of draws.shadow.local
  uint32_t slice_draws[kLocalShadowSlices];
  uint32_t slice_triangles[kLocalShadowSlices];
  uint32_t slice_light[kLocalShadowSlices];         // frame.lights index of each map's light
  uint32_t candidate_light[kLocalShadowRecorded];   // frame.lights index of the first candidates, by rank
  uint32_t candidate_reason[kLocalShadowRecorded];  // LocalShadowReason
};
static_assert(sizeof(LocalShadowPlan) == (8 + 4 * kLocalShadowSlices + 2 * kLocalShadowRecorded) * 4);

inline BufferSchema local_shadows_schema() {
  using S = GpuLocalShadows;
  return BufferSchema::of<S>()
      .field("clip_x", &S::clip_x)
      .field("clip_y", &S::clip_y)
      .field("clip_z", &S::clip_z)
      .field("clip_w", &S::clip_w)
      .field("depth_range", &S::depth_range)
      .field("counts", &S::counts);
}

inline BufferSchema local_shadow_plan_schema() {
  using S = LocalShadowPlan;
  return BufferSchema::of<S>()
      .field("candidates", &S::candidates)
      .field("maps", &S::maps)
      .field("dropped", &S::dropped)
      .field("draws", &S::draws)
      .field("triangles", &S::triangles)
      .field("max_maps", &S::max_maps)
      .field("slice_first_draw", &S::slice_first_draw)
      .field("slice_draws", &S::slice_draws)
      .field("slice_triangles", &S::slice_triangles)
      .field("slice_light", &S::slice_light)
      .field("candidate_light", &S::candidate_light)
      .field("candidate_reason", &S::candidate_reason);
}

}  // namespace nightcap
