// What gbuffer.opaque and gbuffer.dynamic both record: the draws of one list into the G-buffer,
// with each material's textures bound at the slots surface.glsl reads.
#pragma once

#include <string>

#include "passes/core/context.h"

namespace nightcap {

void draw_surfaces(PassContext& ctx, const std::string& draws);

}  // namespace nightcap
