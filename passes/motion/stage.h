// The constructors of the motion stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl motion_stencil_pass();

}  // namespace nightcap
