// frame.constants: the camera, sun and frame facts every pass reads (passes/frame/constants.cpp).
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl frame_constants_pass();

}  // namespace nightcap
