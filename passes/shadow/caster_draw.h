// Shadow casters: their draw record, as shadow.cull, shadow.distant_plan and shadow.local_plan
// list them, and what the shadow map passes (cascades, distant levels, spot light maps) share to
// draw them.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include <string>
#include <vector>

#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.glsl.h"

namespace nightcap {

namespace kinds {
// Depth from a light's view, forward: 0 at the light's near plane, 1 where nothing was drawn
// (the shadow maps: each a D32 array of cascades, levels or slices).
inline constexpr ResourceKind light_depth{"light_depth"};
}  // namespace kinds

// Whether instances of material `m` are drawn into shadow maps: opaque ones alone (a depth-only
// draw has no alpha test, and a blended surface casts no hard shadow), and no decal.
inline bool casts_shadow(const GpuMaterial& m) {
  return m.extra.z == float(AlphaMode::opaque) && (int(m.extra.w) & 4) == 0;
}

// A shadow map holds no motion, so the previous model is the model. `relative_model`: the
// instance's model matrix relative to the camera, as every draw list.
GpuDraw caster_draw(uint32_t instance, const InstanceRecord& record, const glm::dmat4& relative_model,
                    const MeshRecord& mesh);

// The order the shadow plans list draws in: by material, then mesh, then instance, so draws of
// one mesh follow each other and a list does not depend on the order a walk found its casters.
void sort_for_batching(std::vector<GpuDraw>& draws);

// A shadow map pass's output: `layers` square D32 layers of its `resolution` parameter's side,
// cleared to 1 (no caster; forward depth, LESS).
ImageDecl shadow_depth_array(uint32_t layers);

// Binds the pass's declared pipeline and bindings (vertex_pull.glsl's vertex streams and draw
// list, and the maps' matrices) and `layer` as the push constant that picks a map.
void bind_casters(PassContext& ctx, uint32_t layer);

// Draws `range` of `draws` with what bind_casters bound: depth only, no material.
void draw_casters(PassContext& ctx, const std::string& draws, DrawRange range);

}  // namespace nightcap
