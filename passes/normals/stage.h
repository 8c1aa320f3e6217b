// The constructors of the normal-packing stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl normals_bfn_lut_pass();
PassDecl normals_pack_pass();
PassDecl normals_half_pass();

}  // namespace nightcap
