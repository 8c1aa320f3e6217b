// The constructors of the decal stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl decals_normal_copy_pass();
PassDecl decals_mesh_pass();
PassDecl decals_projected_pass();

}  // namespace nightcap
