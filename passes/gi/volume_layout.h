// What the GI volume's passes hand each other: gi.plan (CPU) writes where the volume lies
// (gi.volume_data), which cells gi.volume gathers this frame (gi.refresh) and its decision
// (gi.plan, which the next frame reads back as history).
#pragma once

#include <cstdint>

#include "passes/core/buffer_schema.h"
#include "passes/core/params.h"
#include "passes/gi/volume_layout.glsl.h"

namespace nightcap {

static_assert(sizeof(GpuGiVolume) == 48);
static_assert(sizeof(GiVolumeConstants) == 48);

// Cells per side of the volume: gi.plan places them, gi.volume sizes its image by them.
inline ParamDecl gi_cells_param() {
  return ParamDecl::integer("cells", 64, 4, 128, "cells per side of the GI volume").shared_by("gi");
}

// Why gi.plan has the whole volume gathered this frame, or not (GiPlan::refresh).
enum class GiRefresh : uint32_t {
  kept = 0,         // gi.refresh lists what is gathered (cells scrolled in, probes captured), the rest is kept
  no_history = 1,   // frame 0, a camera cut
  changed = 2,      // the cells per side or a cell's size changed
  sky_changed = 3,  // the sky seen from the camera changed (sky.atmosphere's record)
  jumped = 4,       // the camera moved a whole volume or more: no cell of the previous one is in this one
};

// Why a box of gi.refresh is gathered.
enum class GiBoxReason : uint32_t {
  whole = 0,           // the whole volume (GiPlan::refresh says why)
  scrolled_in = 1,     // cells that were outside the previous frame's volume
  probe_captured = 2,  // cells inside the box of a probe captured this frame
};

// A box of cells gathered this frame, in world cell indices.
struct GiBox {
  int32_t min[3];
  uint32_t reason;  // GiBoxReason
  uint32_t size[3];
  uint32_t cells;  // size[0] · size[1] · size[2]
};
static_assert(sizeof(GiBox) == 32);

// gi.plan's record.
struct GiPlan {
  uint32_t refresh;          // GiRefresh
  int32_t origin_cell[3];    // the world index of the volume's lowest cell
  uint32_t cells;            // per side
  float cell_metres;         // a cell's side
  uint32_t boxes;            // in gi.refresh
  uint32_t refreshed_cells;  // gathered this frame, counted once per box that holds them
};
static_assert(sizeof(GiPlan) == 32);

inline BufferSchema gi_volume_schema() { return NC_SCHEMA_OF(GpuGiVolume, NC_GPU_GI_VOLUME_FIELDS); }

inline BufferSchema gi_box_schema() {
  using S = GiBox;
  return BufferSchema::of<S>()
      .field("min", &S::min)
      .field("reason", &S::reason)
      .field("size", &S::size)
      .field("cells", &S::cells);
}

inline BufferSchema gi_plan_schema() {
  using S = GiPlan;
  return BufferSchema::of<S>()
      .field("refresh", &S::refresh)
      .field("origin_cell", &S::origin_cell)
      .field("cells", &S::cells)
      .field("cell_metres", &S::cell_metres)
      .field("boxes", &S::boxes)
      .field("refreshed_cells", &S::refreshed_cells);
}

}  // namespace nightcap
