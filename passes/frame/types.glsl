// The structs shaders share with C++, and what only shaders need.
#include "gpu_types.glsl.h"

const uint LIGHT_DIRECTIONAL = 0u;
const uint LIGHT_POINT = 1u;
const uint LIGHT_SPOT = 2u;
const uint LIGHT_TUBE = 3u;

const float PI = 3.14159265358979;
