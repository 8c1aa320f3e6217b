// What bloom's shader shares with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_POST_BLOOM_GLSL_H
#define NIGHTCAP_POST_BLOOM_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Pixels on a side of a workgroup's tile.
NC_CONST(uint, kBloomTile, 16u)

#endif
