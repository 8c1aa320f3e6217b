// The constructors of the GI volume's passes, which the frame's assembly
// (passes/assembly/registry.cpp) puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl gi_plan_pass();
PassDecl gi_volume_pass();

}  // namespace nightcap
