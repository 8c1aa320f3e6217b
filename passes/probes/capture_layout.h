// The probes' per-face and per-slot records (capture_layout.glsl.h) and their schemas.
#pragma once

#include "passes/core/buffer_schema.h"
#include "passes/probes/capture_layout.glsl.h"

namespace nightcap {

static_assert(sizeof(GpuProbeFace) == 16);
static_assert(sizeof(GpuProbeSlot) == 48);

BufferSchema probe_face_schema();
BufferSchema probe_slot_schema();

}  // namespace nightcap
