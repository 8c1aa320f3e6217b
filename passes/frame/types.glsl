// The structs shaders share with C++, and what only shaders need.
#include "gpu_types.glsl.h"

#include "../scene/light_type.glsl.h"

const float PI = 3.14159265358979;
