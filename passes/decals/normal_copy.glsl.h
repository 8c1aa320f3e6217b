// What decals.normal_copy's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_DECALS_NORMAL_COPY_GLSL_H
#define NIGHTCAP_DECALS_NORMAL_COPY_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup.
NC_CONST(uint, kNormalCopyGroupSide, 8u)

#endif
