// The constructors of the reflection probes' passes, which the frame's assembly
// (passes/assembly/registry.cpp) puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl probes_plan_pass();
PassDecl probes_cull_pass();
PassDecl probes_gbuffer_pass();
PassDecl probes_light_pass();
PassDecl probes_keep_pass();
PassDecl probes_convert_pass();
PassDecl probes_irradiance_pass();

}  // namespace nightcap
