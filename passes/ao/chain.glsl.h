// What the ambient-occlusion chain's shaders share with passes/ao/chain.cpp
// (passes/core/gpu_layout.glsl.h says how this header is read by both compilers).
#ifndef NIGHTCAP_AO_CHAIN_GLSL_H
#define NIGHTCAP_AO_CHAIN_GLSL_H

#include "../core/gpu_layout.glsl.h"

// The 8-bit code of a stored vector's zero component, 128 as normals.packed stores it (not 0.5,
// which devices may round either way). Where there is nothing to occlude the chain's images hold
// the zero vector and visibility 1: their clear value and what the shaders store there.
NC_CONST(float, kAoZeroComponent, 128.0 / 255.0)

#endif
