// What motion.stencil's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_MOTION_STENCIL_GLSL_H
#define NIGHTCAP_MOTION_STENCIL_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup's tile.
NC_CONST(uint, kMotionStencilTile, 16u)

#endif
