// What the local-light shadow passes hand each other (frame.md section 1, shadow.local):
// shadow.local_plan (CPU) picks the spot lights that get a map this frame and writes their
// projections (shadow.local_data, read by shadow.local_moments and lighting.tiled), the
// projections the maps are drawn with (shadow.local_views, per cache slot), which map each light
// of frame.lights uses (shadow.local_slots), one draw list per map packed into
// draws.shadow.local, and its recorded decision (shadow.local_plan), which it reads back a frame
// later. shadow.local_static keeps each slot's static casters' depth across frames;
// shadow.local lays map k's slot down and draws the moving casters over it.
#pragma once

#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <span>
#include <string>

#include "passes/core/buffer_schema.h"
#include "passes/core/graph.h"
#include "passes/shadow/local_layout.glsl.h"

namespace nightcap {

constexpr uint32_t kLocalShadowResolution = 512;
// The moments' blur radius shadow.local_moments supports at most (its shared-memory tile).
constexpr uint32_t kLocalShadowMaxBlur = 4;

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

static_assert(sizeof(GpuLocalShadowViews) == kLocalShadowSlices * 64);

// Why a spot light has a map this frame or not (LocalShadowPlan::candidate_reason).
enum class LocalShadowReason : uint32_t {
  refreshed = 1,        // has a map; its static casters' depth drawn this frame (LocalSlotState says why)
  over_budget = 2,      // a shadow-casting light in view, but max_maps nearer or larger ones took the maps
  unbounded_range = 3,  // range 0: no far plane for a map
  reused = 4,           // has a map; its static casters' depth kept from the previous frame
  throttled = 5,        // would have a map but needs a refresh, and max_refreshes were spent: none this frame
};

// What each cache slot of shadow.local_static holds this frame (LocalShadowPlan::slot_state).
enum class LocalSlotState : uint32_t {
  empty = 0,              // no light: cleared
  reused = 1,             // the same light and view as the previous frame's: copied from history, and it has a map
  kept = 2,               // the same, for a light without a map this frame (kept for when it returns)
  refreshed_new = 3,      // a light new to the slot: cleared and its static casters drawn
  refreshed_changed = 4,  // the same light, but its view differs from the previous frame's (near_metres changed)
  refreshed_reset = 5,    // no history: the first frame or a camera cut
  refreshed_cache_off = 6,
};

// scene.lights index of a slot without a light.
constexpr uint32_t kLocalNoLight = 0xffffffffu;

// Candidates the record names (the rest are counted): the capture's schema holds arrays of at most 64.
constexpr uint32_t kLocalShadowRecorded = 64;

// What shadow.local_plan decided, as the capture records it (and reads back a frame later).
struct LocalShadowPlan {
  uint32_t candidates;  // spot lights in frame.lights (in view)
  uint32_t maps;        // maps this frame: layers [0, maps) of shadow.local
  uint32_t dropped;     // candidates without a map (over budget, unbounded or throttled)
  uint32_t draws, triangles;
  uint32_t max_maps;
  uint32_t refreshed;  // slots whose static casters were drawn this frame
  uint32_t max_refreshes;
  uint32_t reused;                                // maps whose static depth was kept
  uint32_t throttled;                             // candidates left without a map for want of a refresh
  uint32_t cache;                                 // the `cache` parameter
  uint32_t reset;                                 // 1: no history this frame (first frame or a camera cut)
  uint32_t slice_first_draw[kLocalShadowSlices];  // map k's range of draws.shadow.local: static casters, then moving
  uint32_t slice_draws[kLocalShadowSlices];
  uint32_t slice_moving_draws[kLocalShadowSlices];
  uint32_t slice_triangles[kLocalShadowSlices];
  uint32_t slice_light[kLocalShadowSlices];         // frame.lights index of each map's light
  uint32_t slice_slot[kLocalShadowSlices];          // the shadow.local_static slot each map starts from
  uint32_t slot_light[kLocalShadowSlices];          // scene.lights index each slot holds, or kLocalNoLight
  uint32_t slot_state[kLocalShadowSlices];          // LocalSlotState
  uint32_t slot_idle[kLocalShadowSlices];           // frames since the slot's light last had a map
  uint32_t candidate_light[kLocalShadowRecorded];   // frame.lights index of the first candidates, by rank
  uint32_t candidate_reason[kLocalShadowRecorded];  // LocalShadowReason
  // The layer of the previous frame's shadow.local_moments that holds map k's moments but where
  // moving casters are or were, or -1: its slot reused (the same static depth) and the previous
  // frame had a map of that slot, with the same `moments`. shadow.local_moments copies that layer
  // and computes again only moments_dirty[k]: in the map's NDC (x0, y0, x1, y1), the box around
  // every moving caster that meets the light's range, where it is and where it was a frame
  // earlier (x0 > x1: none).
  int32_t moments_from[kLocalShadowSlices];
  glm::vec4 moments_dirty[kLocalShadowSlices];
  uint32_t moments;  // the `moments` parameter (shadow.local_data's counts.y)
  uint32_t pad[3];
};
static_assert(sizeof(LocalShadowPlan) == (16 + 14 * kLocalShadowSlices + 2 * kLocalShadowRecorded) * 4);

inline BufferSchema local_shadows_schema() { return NC_SCHEMA_OF(GpuLocalShadows, NC_GPU_LOCAL_SHADOWS_FIELDS); }

inline BufferSchema local_shadow_views_schema() {
  return NC_SCHEMA_OF(GpuLocalShadowViews, NC_GPU_LOCAL_SHADOW_VIEWS_FIELDS);
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
      .field("refreshed", &S::refreshed)
      .field("max_refreshes", &S::max_refreshes)
      .field("reused", &S::reused)
      .field("throttled", &S::throttled)
      .field("cache", &S::cache)
      .field("reset", &S::reset)
      .field("slice_first_draw", &S::slice_first_draw)
      .field("slice_draws", &S::slice_draws)
      .field("slice_moving_draws", &S::slice_moving_draws)
      .field("slice_triangles", &S::slice_triangles)
      .field("slice_light", &S::slice_light)
      .field("slice_slot", &S::slice_slot)
      .field("slot_light", &S::slot_light)
      .field("slot_state", &S::slot_state)
      .field("slot_idle", &S::slot_idle)
      .field("candidate_light", &S::candidate_light)
      .field("candidate_reason", &S::candidate_reason)
      .field("moments_from", &S::moments_from)
      .field("moments_dirty", &S::moments_dirty)
      .field("moments", &S::moments);
}

}  // namespace nightcap
