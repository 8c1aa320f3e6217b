// What probes.irradiance's shader shares with its pass (passes/core/gpu_layout.glsl.h says how
// this header is read by both compilers).
#ifndef NIGHTCAP_PROBES_IRRADIANCE_GLSL_H
#define NIGHTCAP_PROBES_IRRADIANCE_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_PROBE_IRRADIANCE_CONSTANTS_FIELDS(F, A, P)                                   \
  /* the slot written */                                                                \
  F(uint, slot)                                                                         \
  /* the cube of probes.faces captured for it this frame */                             \
  F(uint, capture)                                                                      \
  /* the level of probes.faces projected: the first no wider than kSkyIrradianceFace */ \
  F(uint, level)
NC_PUSH_CONSTANTS(ProbeIrradianceConstants, NC_PROBE_IRRADIANCE_CONSTANTS_FIELDS)

#endif
