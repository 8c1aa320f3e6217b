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

// probes.slots: what each slot of probes.array holds, for the passes that read the array.
#define NC_GPU_PROBE_SLOT_FIELDS(F, A, P)                                              \
  /* xyz: the probe's position relative to the camera; w: 1 when the slot holds a      \
     capture (captured this frame or before), 0 when it is empty or waiting for one */ \
  F(vec4, position)                                                                    \
  /* the probe's parallax box, relative to the camera (w unused) */                    \
  F(vec4, box_min)                                                                     \
  F(vec4, box_max)
NC_STRUCT(GpuProbeSlot, NC_GPU_PROBE_SLOT_FIELDS)

#endif
