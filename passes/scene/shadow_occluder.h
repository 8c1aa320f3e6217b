// Which instances are safe occluders for a shadow map drawn at any level of detail, whatever
// the camera: what the time-of-day bake rasterises as occluders and what shadow.distant draws
// into its occluder layer for shadow.cull.
#pragma once

#include <cstdint>

#include "passes/scene/scene.h"

namespace nightcap {

// The number of leading indices of the instance's finest mesh that every level of detail it may
// be drawn at draws too (the same positions, to a millimetre), at any distance: triangles that
// are in every shadow map the instance is drawn into, however far and at whatever level. 0 when
// the instance is no such occluder: moving, not opaque, a decal, a level with a finite draw
// distance or another prefix, a degenerate transform.
uint32_t shadow_occluder_indices(const Scene& scene, uint32_t instance);

}  // namespace nightcap
