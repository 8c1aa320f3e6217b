// What the sun's shadow passes hand each other: shadow.cull (CPU) writes the cascades'
// projections (shadow.cascade_data, read by shadow.cascades and shadow.sun_resolve), one draw
// list per cascade packed into draws.shadow.cascades, and what it culled (shadow.cull_stats).
// shadow.distant_plan (CPU) writes the distant levels' projections and this frame's refresh
// (shadow.distant_data, read by shadow.distant and shadow.sun_resolve), the draws of the
// refreshed tiles (draws.shadow.distant) and the recorded decision (shadow.distant_plan).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "passes/core/buffer_schema.h"
#include "passes/shadow/shadow_layout.glsl.h"

namespace nightcap {

struct GraphicsPipelineDesc;

// Texels per side of each cascade by default (the group parameter shadow.resolution,
// passes/shadow/shadow_params.h).
constexpr uint32_t kShadowResolution = 1024;
// Tiles per side of a cascade at most: a cascade's tiles are one 64-bit mask (two 32-bit words).
constexpr uint32_t kCascadeMaxTilesPerSide = 8;
constexpr uint32_t kCascadeUnits = kShadowCascades * kCascadeMaxTilesPerSide * kCascadeMaxTilesPerSide;

static_assert(sizeof(GpuShadowCascades) == 4 * 64 + 4 * 16 + 4 * 16);

// Why shadow.cull redraws the cascades' static layers without what the previous frame held
// (ShadowCullStats::reset).
enum class CascadeReset : uint32_t {
  none = 0,           // the layers carry over; the uncovered strips and stale tiles are redrawn, within the budget
  no_history = 1,     // frame 0, a camera cut, or a previous frame without cascades
  frame_changed = 2,  // the sun, the light depth's range, the lens's cascades or a parameter moved the layers' frame
  cache_off = 3,      // `cache` 0: every static layer drawn whole each frame (culled by its volume and the view)
  // After any reset the static layers are drawn whole, whatever the budget.
};

// What shadow.cull decided this frame: what it culled, the draws of each cascade and the static
// layers' refresh, as the capture records it; the next frame's shadow.cull reads it back as its
// history. A unit is one tile of one cascade, numbered cascade · tiles² + ty · tiles + tx; a
// cascade's tile masks are 64 bits, words 2k (low) and 2k + 1 (high).
struct ShadowCullStats {
  uint32_t casters_tested[kShadowCascades];  // instances looked at, and every instance of a culled node
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
  // Each cascade's range of draws lists the static casters of its redrawn tiles first (tile by
  // tile; with the cache off, of the whole layer), then these many moving ones.
  uint32_t moving_draws[kShadowCascades];
  // Casters that passed the volume and the view's occluders but lie wholly behind
  // shadow.distant_occluders from the sun (kept when culling=0), and their triangles.
  uint32_t casters_light_hidden[kShadowCascades];
  uint32_t light_hidden_triangles[kShadowCascades];
  uint32_t reset;  // CascadeReset
  uint32_t tiles_per_side;
  uint32_t budget_triangles;  // static triangles drawn per frame at most (a unit above it is drawn alone)
  uint32_t over_budget;       // 1 when a unit drawn this frame alone exceeds the budget
  uint32_t pending;           // units (a tile, or a cascade's strips) still stale after this frame
  uint32_t static_triangles;  // static triangles drawn this frame
  uint32_t level_changes;     // static casters drawn at another level of detail, or not at all, than a frame earlier
  uint32_t resolution;
  // Each cascade's centre in whole texels of world light space: where the next frame's layers
  // find what this one holds; and the texel of the previous frame's layer that this frame's
  // texel (0, 0) covers (the layer moved with the camera by whole texels).
  int32_t centre[2 * kShadowCascades];
  int32_t shift[2 * kShadowCascades];
  uint32_t stale[2 * kShadowCascades];  // tiles that did not hold their casters' depth before this frame
  uint32_t
      needed[2 * kShadowCascades];  // tiles the cascade's slice (grown by the filter's margin) covers: redrawn first
  uint32_t refreshed[2 * kShadowCascades];  // tiles redrawn this frame
  uint32_t complete[2 * kShadowCascades];   // tiles that hold their casters' depth after it
  // Stale tiles that missed only the texels the move uncovered: complete again once the
  // cascade's strips (those texels: uncovered_strips in passes/shadow/light_tiles.h) are drawn.
  uint32_t partial[2 * kShadowCascades];
  uint32_t strips;  // bit k: cascade k's strips drawn this frame
  uint32_t strip_first_draw[kShadowCascades];
  uint32_t strip_draws[2 * kShadowCascades];  // per cascade, the columns' draws, then the rows'
  uint32_t strip_triangles[kShadowCascades];  // of the cascade's strips, drawn this frame or not
  // The layers' frame (the sun's direction, the light depth's start and span, each cascade's
  // side, the resolution, the tiles, the time of day's hours): history is kept only while it is
  // the same, bit for bit.
  float frame_key[12];
  uint32_t unit_first_draw[kCascadeUnits];  // this frame's draws.shadow.cascades range of a redrawn unit
  uint32_t unit_draws[kCascadeUnits];
  uint32_t unit_triangles[kCascadeUnits];  // of a stale tile, redrawn this frame or not
  uint32_t unit_waiting[kCascadeUnits];    // of a stale tile, the frames it has waited for its redraw

  static uint64_t mask(const uint32_t (&words)[2 * kShadowCascades], uint32_t cascade) {
    return uint64_t(words[2 * cascade]) | uint64_t(words[2 * cascade + 1]) << 32;
  }
  static void set_mask(uint32_t (&words)[2 * kShadowCascades], uint32_t cascade, uint64_t bits) {
    words[2 * cascade] = uint32_t(bits);
    words[2 * cascade + 1] = uint32_t(bits >> 32);
  }
};
static_assert(sizeof(ShadowCullStats) == (12 * kShadowCascades + 8 + 2 * 2 * kShadowCascades + 5 * 2 * kShadowCascades +
                                          1 + 4 * kShadowCascades + 12 + 4 * kCascadeUnits) *
                                             4);

inline BufferSchema shadow_cascades_schema() { return NC_SCHEMA_OF(GpuShadowCascades, NC_GPU_SHADOW_CASCADES_FIELDS); }

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
      .field("tod_triangles_saved", &S::tod_triangles_saved)
      .field("moving_draws", &S::moving_draws)
      .field("casters_light_hidden", &S::casters_light_hidden)
      .field("light_hidden_triangles", &S::light_hidden_triangles)
      .field("reset", &S::reset)
      .field("tiles_per_side", &S::tiles_per_side)
      .field("budget_triangles", &S::budget_triangles)
      .field("over_budget", &S::over_budget)
      .field("pending", &S::pending)
      .field("static_triangles", &S::static_triangles)
      .field("level_changes", &S::level_changes)
      .field("resolution", &S::resolution)
      .field("centre", &S::centre)
      .field("shift", &S::shift)
      .field("stale", &S::stale)
      .field("needed", &S::needed)
      .field("refreshed", &S::refreshed)
      .field("complete", &S::complete)
      .field("partial", &S::partial)
      .field("strips", &S::strips)
      .field("strip_first_draw", &S::strip_first_draw)
      .field("strip_draws", &S::strip_draws)
      .field("strip_triangles", &S::strip_triangles)
      .field("frame_key", &S::frame_key)
      .field("unit_first_draw", &S::unit_first_draw)
      .field("unit_draws", &S::unit_draws)
      .field("unit_triangles", &S::unit_triangles)
      .field("unit_waiting", &S::unit_waiting);
}

// Tiles per side of a level at most: a level's refreshed tiles are one 16-bit mask.
constexpr uint32_t kDistantMaxTilesPerSide = 4;
constexpr uint32_t kDistantTiles = kDistantMaxTilesPerSide * kDistantMaxTilesPerSide;  // per level, at most
constexpr uint32_t kDistantUnits = kDistantLevels * kDistantTiles;
constexpr uint32_t kDistantResolution = 1024;

static_assert(sizeof(GpuDistantLevels) == 4 * 64 + 3 * 16 + 4 * 16);

// Why shadow.distant_plan redraws every unit this frame, past the budget (DistantPlan::reset).
enum class DistantReset : uint32_t {
  none = 0,            // the levels carry over; only stale units are redrawn, within the budget
  no_history = 1,      // frame 0, a camera cut, or a previous frame without levels
  levels_changed = 2,  // the sun, the static scene's extent or the parameters moved the levels' frame
  cache_off = 3,       // `cache` 0: every level drawn whole each frame
};

// What shadow.distant_plan decided this frame, as the capture records it, and what the next
// frame's plan reads back as its history. A unit is one tile of one level, numbered
// level · tiles² + ty · tiles + tx; masks are per level, bit ty · tiles + tx.
struct DistantPlan {
  uint32_t reset;  // DistantReset
  uint32_t tiles_per_side;
  uint32_t budget_triangles;           // per frame
  uint32_t stale[kDistantLevels];      // units that did not hold their casters' depth before this frame
  uint32_t refreshed[kDistantLevels];  // units redrawn this frame
  uint32_t complete[kDistantLevels];   // units that hold their casters' depth after it
  uint32_t draws, triangles;           // drawn this frame
  uint32_t over_budget;                // 1 when a unit drawn this frame alone exceeds the budget (it is drawn whole)
  uint32_t units;                      // levels · tiles²
  uint32_t pending;                    // units still stale after this frame
  uint32_t resolution;
  // Each level's centre in whole texels of world light space (x, y): where the next frame's
  // levels find what this one holds.
  int32_t centre[2 * kDistantLevels];
  // The levels' frame (the sun's direction, the finest level's side, the light depth's start and
  // span): history is kept only while it is the same, bit for bit.
  float frame_key[6];
  uint32_t unit_triangles[kDistantUnits];   // every unit's triangles, redrawn this frame or not
  uint32_t unit_first_draw[kDistantUnits];  // this frame's draws.shadow.distant range of a redrawn unit
  uint32_t unit_draws[kDistantUnits];
  // Per tile of level 0 redrawn this frame, the draws.shadow.distant range of its shadow
  // occluders (kInstanceShadowOccluder, their occluder triangles): shadow.distant_occluders.
  uint32_t occluder_first_draw[kDistantTiles];
  uint32_t occluder_draws[kDistantTiles];
};
static_assert(sizeof(DistantPlan) ==
              (9 + 3 * kDistantLevels + 2 * kDistantLevels + 6 + 3 * kDistantUnits + 2 * kDistantTiles) * 4);

inline BufferSchema distant_levels_schema() { return NC_SCHEMA_OF(GpuDistantLevels, NC_GPU_DISTANT_LEVELS_FIELDS); }

inline BufferSchema distant_plan_schema() {
  using S = DistantPlan;
  return BufferSchema::of<S>()
      .field("reset", &S::reset)
      .field("tiles_per_side", &S::tiles_per_side)
      .field("budget_triangles", &S::budget_triangles)
      .field("stale", &S::stale)
      .field("refreshed", &S::refreshed)
      .field("complete", &S::complete)
      .field("draws", &S::draws)
      .field("triangles", &S::triangles)
      .field("over_budget", &S::over_budget)
      .field("units", &S::units)
      .field("pending", &S::pending)
      .field("resolution", &S::resolution)
      .field("centre", &S::centre)
      .field("frame_key", &S::frame_key)
      .field("unit_triangles", &S::unit_triangles)
      .field("unit_first_draw", &S::unit_first_draw)
      .field("unit_draws", &S::unit_draws)
      .field("occluder_first_draw", &S::occluder_first_draw)
      .field("occluder_draws", &S::occluder_draws);
}

}  // namespace nightcap
