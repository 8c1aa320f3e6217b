// What depth.pyramid's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_DEPTH_PYRAMID_GLSL_H
#define NIGHTCAP_DEPTH_PYRAMID_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Texels of the target mip on a side of a workgroup.
NC_CONST(uint, kPyramidGroupSide, 8u)

#endif
