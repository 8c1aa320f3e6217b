// What gbuffer.opaque and gbuffer.dynamic share: the inputs of a pass that draws one list into
// the G-buffer, and what it records: the draws, with each material's textures bound at the slots
// surface.glsl reads.
#pragma once

#include <string>

#include "passes/core/context.h"

namespace nightcap {

// Binds what the pass declares (decals.mesh adds its normal copy), then draws.
void draw_surfaces(PassContext& ctx, const std::string& draws);

// A graphics pass that reads the views (frame.views), the scene's geometry, materials and
// textures and the draw list `draws`, depth-tests against scene.depth, culls back faces per draw
// and runs draw_surfaces; the caller adds its targets, depth state, skip condition and shaders.
PassDecl surface_pass(std::string name, const std::string& draws);

}  // namespace nightcap
