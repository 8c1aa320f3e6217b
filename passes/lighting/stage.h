// The constructors of the lighting stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl lighting_ltc_table_pass();
PassDecl lighting_dfg_pass();
PassDecl lighting_tiled_pass();
PassDecl lighting_deferred_pass();
PassDecl lighting_composite_pass();

}  // namespace nightcap
