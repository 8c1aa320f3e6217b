// Issues the draws of a `draws.<pass>` list: binds scene.geometry's index stream, sets the
// cull mode per material (double-sided ones are not culled) and the stencil reference per
// draw, and calls `on_material` whenever the material changes (draws are sorted by it).
#pragma once

#include <functional>
#include <string>

#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"

namespace nightcap {

void draw_scene(PassContext& ctx, const std::string& draws,
                const std::function<void(uint32_t material, const GpuMaterial&)>& on_material);

// Bindings 0-2 of geometry.glsl: frame constants, vertex stream, draw list.
std::vector<Binding> geometry_bindings(PassContext& ctx, const std::string& draws);

}  // namespace nightcap
