#include "passes/frame/view.h"

#include <glm/gtc/matrix_transform.hpp>

#include "passes/frame/camera_math.h"

namespace nightcap {

GpuView perspective_view(const ViewPlacement& placement, const std::optional<glm::dmat4>& previous_view_projection) {
  const double aspect = double(placement.width) / placement.height;
  const glm::dmat4 view =
      glm::inverse(glm::dmat4(placement.orientation)) * glm::translate(glm::dmat4(1.0), -placement.eye);
  const glm::dmat4 unjittered = reversed_z_projection(placement.yfov, aspect, placement.znear);
  // Moves what is drawn by `jitter` pixels: NDC spans 2 over the viewport; w is -z in view space.
  glm::dmat4 projection = unjittered;
  projection[2][0] -= 2.0 * placement.jitter.x / placement.width;
  projection[2][1] -= 2.0 * placement.jitter.y / placement.height;
  const glm::dmat4 view_projection = projection * view;
  GpuView v{};
  v.view = glm::mat4(view);
  v.projection = glm::mat4(projection);
  v.view_projection = glm::mat4(view_projection);
  v.inverse_view_projection = glm::mat4(glm::inverse(view_projection));
  v.previous_view_projection = glm::mat4(previous_view_projection.value_or(unjittered * view));
  v.eye = glm::vec4(glm::vec3(placement.eye), 1.0f);
  v.viewport = {float(placement.width), float(placement.height), 1.0f / placement.width, 1.0f / placement.height};
  v.projection_params = {float(placement.znear), float(placement.yfov), float(aspect), 0.0f};
  v.jitter = {float(placement.jitter.x), float(placement.jitter.y), float(placement.jitter.x / placement.width),
              float(placement.jitter.y / placement.height)};
  return v;
}

}  // namespace nightcap
