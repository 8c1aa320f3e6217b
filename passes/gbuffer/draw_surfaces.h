// What the passes that draw surfaces with surface.glsl share (gbuffer.opaque, gbuffer.dynamic,
// decals.mesh, probes.gbuffer): their inputs, and what they record: the draws, with each
// material's textures bound at the slots surface.glsl reads.
#pragma once

#include <string>

#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"

namespace nightcap {

// Binds what the pass declares (decals.mesh adds its normal copy), then draws `range` of `draws`
// into the attachments the caller began rendering to.
void draw_surfaces(PassContext& ctx, const std::string& draws, DrawRange range = {});

// A graphics pass that reads the view list `views` (as `views`), the scene's geometry, materials
// and textures and the draw list `draws` (as `draws`) and culls back faces per draw; the caller
// adds its targets, depth, skip condition, shaders and run.
PassDecl surface_drawing_pass(std::string name, const std::string& views, const std::string& draws);

// A surface_drawing_pass from the frame's camera (frame.views), depth-tested against scene.depth,
// that draws the whole list into its declared attachments.
PassDecl surface_pass(std::string name, const std::string& draws);

}  // namespace nightcap
