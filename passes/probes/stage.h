// The constructors of the reflection probes' passes, which the frame's assembly
// (passes/assembly/registry.cpp) puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl probes_plan_pass();

}  // namespace nightcap
