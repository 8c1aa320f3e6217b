// What the top-down map's passes hand each other: shadow.topdown_plan (CPU) writes the map's
// projection (shadow.topdown_data), the static casters to draw when the map is redrawn
// (draws.shadow.topdown) and its decision (shadow.topdown_plan), which the next frame reads
// back as history; shadow.topdown draws or carries the map; lighting.composite and
// probes.light read both (topdown.glsl).
#pragma once

#include <cstdint>

#include "passes/core/buffer_schema.h"
#include "passes/shadow/topdown_layout.glsl.h"

namespace nightcap {

static_assert(sizeof(GpuTopdown) == 64 + 16);

// Why shadow.topdown_plan redraws the map this frame (TopdownPlan::refresh).
enum class TopdownRefresh : uint32_t {
  kept = 0,        // the map is carried over from the previous frame
  no_history = 1,  // frame 0, a camera cut
  moved = 2,       // the camera crossed into another eighth of the map's side
  changed = 3,     // the static scene's height range or the parameters changed the map's frame
};

// shadow.topdown_plan's record: what the map holds and what this frame did.
struct TopdownPlan {
  uint32_t refresh;  // TopdownRefresh
  uint32_t resolution;
  int32_t centre[2];  // the map's centre in whole texels of world x and z
  // The map's frame (its side in metres, the heights z = 0 and 1 stand for): history is kept
  // only while it is the same, bit for bit.
  float side_metres, top, bottom;
  uint32_t draws, triangles;  // drawn this frame
};
static_assert(sizeof(TopdownPlan) == 9 * 4);

inline BufferSchema topdown_schema() { return NC_SCHEMA_OF(GpuTopdown, NC_GPU_TOPDOWN_FIELDS); }

inline BufferSchema topdown_plan_schema() {
  using S = TopdownPlan;
  return BufferSchema::of<S>()
      .field("refresh", &S::refresh)
      .field("resolution", &S::resolution)
      .field("centre", &S::centre)
      .field("side_metres", &S::side_metres)
      .field("top", &S::top)
      .field("bottom", &S::bottom)
      .field("draws", &S::draws)
      .field("triangles", &S::triangles);
}

}  // namespace nightcap
