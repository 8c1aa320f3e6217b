// The constructors of the light-list stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl lights_cluster_pass();

}  // namespace nightcap
