// The constructors of the shadow stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl shadow_distant_plan_pass();
PassDecl shadow_distant_pass();
PassDecl shadow_topdown_plan_pass();
PassDecl shadow_topdown_pass();
PassDecl shadow_cull_pass();
PassDecl shadow_cascades_pass();
PassDecl shadow_cascades_static_pass();
PassDecl shadow_sun_resolve_pass();
PassDecl shadow_local_plan_pass();
PassDecl shadow_local_static_pass();
PassDecl shadow_local_pass();
PassDecl shadow_local_moments_pass();

}  // namespace nightcap
