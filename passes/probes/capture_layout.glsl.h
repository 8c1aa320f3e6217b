// What the reflection probes' passes share with C++ (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers): per captured face, its draws and lights; per slot, its probe.
#ifndef NIGHTCAP_PROBES_CAPTURE_LAYOUT_GLSL_H
#define NIGHTCAP_PROBES_CAPTURE_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Probes in one texture array [000]: the nearest this many in range hold a slot.
NC_CONST(uint, kProbeSlots, 32u)

// probes.face_draws: one per view of probes.views (six per captured probe, in the same order).
#define NC_GPU_PROBE_FACE_FIELDS(F, A, P)                                     \
  /* the face's range of draws.probes */                                      \
  F(uint, first_draw)                                                         \
  F(uint, draws)                                                              \
  /* the capture's range of probes.lights (the same for the probe's faces) */ \
  F(uint, first_light)                                                        \
  F(uint, lights)
NC_STRUCT(GpuProbeFace, NC_GPU_PROBE_FACE_FIELDS)

// probes.slots: the slots of probes.array that hold a capture, for the passes that read it.
#define NC_GPU_PROBE_SLOT_FIELDS(F, A, P)                             \
  /* xyz: the probe's position relative to the camera; w: its slot */ \
  F(vec4, position)                                                   \
  /* the probe's parallax box, relative to the camera (w unused) */   \
  F(vec4, box_min)                                                    \
  F(vec4, box_max)
NC_STRUCT(GpuProbeSlot, NC_GPU_PROBE_SLOT_FIELDS)

#endif
