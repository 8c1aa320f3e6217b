// The constructors of the culling stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl cull_main_pass();

}  // namespace nightcap
