// The constructors of the ambient-occlusion stage's passes, which the frame's assembly
// (passes/assembly/registry.cpp) puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl ao_gtao_pass();
PassDecl ao_filter_pass();
PassDecl ao_temporal_pass();

}  // namespace nightcap
