// The constructors of the G-buffer stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl gbuffer_opaque_pass();
PassDecl gbuffer_dynamic_pass();

}  // namespace nightcap
