// Issues the draws of a `draws.<pass>` list: binds scene.geometry's index stream, sets the
// declared cull mode per material (double-sided ones are not culled), the declared front face
// per draw (flipped where mirrored) and the stencil reference per draw, and calls
// `on_material` whenever the material changes (draws are sorted by it). The pass declares
// RasterState::per_draw_faces.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"

namespace nightcap {

// The seeds' order inside gbuffer.opaque [001], the class draw lists sort by first: static meshes
// (0), then ground and emissive (1), then foliage (2); destructibles have no class of their own.
uint32_t draw_order_class(const GpuMaterial& m);

// Records [first, first + count) of the list (all by default): a list packing several views'
// draws (shadow.cascades) draws each view's range.
struct DrawRange {
  size_t first = 0, count = SIZE_MAX;
};
void draw_scene(PassContext& ctx, const std::string& draws,
                const std::function<void(uint32_t material, const GpuMaterial&)>& on_material, DrawRange range = {});

}  // namespace nightcap
