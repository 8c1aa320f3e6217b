// What probes.convert's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_PROBES_CONVERT_GLSL_H
#define NIGHTCAP_PROBES_CONVERT_GLSL_H

#include "../core/gpu_layout.glsl.h"

NC_CONST(uint, kProbeConvertGroupSide, 8u)

#define NC_PROBE_CONVERT_CONSTANTS_FIELDS(F, A, P)                          \
  /* the level of probes.array written */                                   \
  F(uint, level)                                                            \
  /* the slot written, and the capture (cube of probes.faces) it is from */ \
  F(uint, slot)                                                             \
  F(uint, capture)                                                          \
  /* GGX samples per texel of the level written (past 0) */                 \
  F(uint, samples)
NC_PUSH_CONSTANTS(ProbeConvertConstants, NC_PROBE_CONVERT_CONSTANTS_FIELDS)

#endif
