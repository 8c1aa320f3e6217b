// What normals.half's shader shares with its pass (passes/core/gpu_layout.glsl.h says how this
// header is read by both compilers).
#ifndef NIGHTCAP_NORMALS_HALF_GLSL_H
#define NIGHTCAP_NORMALS_HALF_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Half-resolution pixels on a side of a workgroup.
NC_CONST(uint, kNormalsHalfGroupSide, 8u)

#endif
