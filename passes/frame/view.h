// GpuView (gpu_types.glsl.h) from a view's placement, in camera_math.h's conventions: computed in
// double and rounded once, so a view kilometres from the camera keeps its precision.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>

#include "passes/frame/gpu_types.h"

namespace nightcap {

struct ViewPlacement {
  // Where the eye stands, relative to the frame's camera.
  glm::dvec3 eye{0.0};
  // The view's axes in world space (columns: right, up, and backward, as a camera's world matrix).
  glm::dmat3 orientation{1.0};
  double yfov = 0, znear = 0;
  uint32_t width = 0, height = 0;
  // TAA's sub-pixel offset of the projection, in pixels (GpuView::jitter).
  glm::dvec2 jitter{0.0};
};

// A perspective view. `previous_view_projection`: where the view was a frame ago, for points
// relative to this frame's camera, unjittered; a view that does not move (none given) reuses this
// frame's unjittered one, so motion vectors hold no jitter.
GpuView perspective_view(const ViewPlacement& placement,
                         const std::optional<glm::dmat4>& previous_view_projection = std::nullopt);

}  // namespace nightcap
