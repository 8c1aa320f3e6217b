// Camera matrices in nightcap's conventions: camera-relative world (the camera sits at the
// origin, so an 8 km city keeps float precision), reversed-Z with an infinite far plane, and
// Vulkan's downward Y folded into the projection.
#pragma once

#include <glm/glm.hpp>

namespace nightcap {

// Depth 1 at the near plane, 0 at infinity.
glm::dmat4 reversed_z_projection(double yfov, double aspect, double znear);
// World orientation → view, for camera-relative positions.
glm::dmat4 relative_view(const glm::dmat4& camera_world);
// Previous frame's view-projection applied to points relative to the current camera.
glm::dmat4 previous_relative_view_projection(const glm::dmat4& previous_world, const glm::dmat4& current_world,
                                             double yfov, double aspect, double znear);

}  // namespace nightcap
