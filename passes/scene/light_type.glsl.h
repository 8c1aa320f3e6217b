// How a light is shaded, one code each for the scene (LightType), frame.lights (GpuLight's
// position_type.w) and the shaders that branch on it (passes/core/gpu_layout.glsl.h says how a
// header is read by both compilers).
#ifndef NIGHTCAP_SCENE_LIGHT_TYPE_GLSL_H
#define NIGHTCAP_SCENE_LIGHT_TYPE_GLSL_H

#include "../core/gpu_layout.glsl.h"

NC_CONST(uint, kLightDirectional, 0u)
NC_CONST(uint, kLightPoint, 1u)
NC_CONST(uint, kLightSpot, 2u)
NC_CONST(uint, kLightTube, 3u)

#endif
