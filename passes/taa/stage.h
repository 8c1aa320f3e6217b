// The constructor of the taa pass, which the frame's assembly (passes/assembly/registry.cpp) puts
// between lighting and post.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl taa_pass();

}  // namespace nightcap
