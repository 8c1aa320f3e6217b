// What probes.plan decided, as the capture records it and the plan reads back a frame later.
#pragma once

#include <cstdint>
#include <span>

#include "passes/core/buffer_schema.h"
#include "passes/core/params.h"
#include "passes/probes/capture_layout.glsl.h"

namespace nightcap {
// The captures' face size: probes.plan's views and probes.gbuffer's targets agree on it
// (`--set probes.face_size=N` sets both).
inline ParamDecl probe_face_size() {
  return ParamDecl::integer("face_size", 64, 8, 512, "texels on a side of a captured cube face").shared_by("probes");
}

// scene.probes index of an empty slot.
constexpr uint32_t kNoProbe = 0xffffffffu;

enum class ProbeSlotState : uint32_t {
  empty = 0,
  captured_reset = 1,  // captured this frame, which has no history (the first frame, a camera cut)
  captured_new = 2,    // captured this frame: it had not been captured since it came in range
  captured_stale = 3,  // captured again this frame: its capture was older than refresh_frames
  up_to_date = 4,      // captured on an earlier frame and still valid
  waiting = 5,         // in range without a capture: over this frame's budget (reflections show the sky)
};

struct ProbePlan {
  uint32_t reset;        // 1: no history this frame, so every probe in range is captured
  uint32_t in_range;     // scene.probes within range_metres of the camera (the nearest kProbeSlots hold slots)
  uint32_t captured;     // probes captured this frame: probes.views [6k, 6k + 6) are capture_slot[k]'s faces
  uint32_t max_updates;  // the budget, after a reset
  uint32_t slot_probe[kProbeSlots];     // scene.probes index, or kNoProbe
  uint32_t slot_state[kProbeSlots];     // ProbeSlotState
  uint32_t slot_captured[kProbeSlots];  // the frame index of the slot's capture (none: waiting or empty)
  uint32_t capture_slot[kProbeSlots];   // the slots captured this frame, in order
};
static_assert(sizeof(ProbePlan) == (4 + 4 * kProbeSlots) * 4);

// The plan a record holds; an empty record (probes.plan skipped: no probes, or disabled) is a
// plan that captures nothing.
ProbePlan read_probe_plan(std::span<const uint8_t> record);

inline BufferSchema probe_plan_schema() {
  using S = ProbePlan;
  return BufferSchema::of<S>()
      .field("reset", &S::reset)
      .field("in_range", &S::in_range)
      .field("captured", &S::captured)
      .field("max_updates", &S::max_updates)
      .field("slot_probe", &S::slot_probe)
      .field("slot_state", &S::slot_state)
      .field("slot_captured", &S::slot_captured)
      .field("capture_slot", &S::capture_slot);
}

}  // namespace nightcap
