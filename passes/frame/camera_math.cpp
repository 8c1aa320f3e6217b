#include "passes/frame/camera_math.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace nightcap {

glm::dmat4 reversed_z_projection(double yfov, double aspect, double znear) {
  const double f = 1.0 / std::tan(yfov / 2.0);
  glm::dmat4 p(0.0);
  p[0][0] = f / aspect;
  p[1][1] = -f;
  p[2][3] = -1.0;
  p[3][2] = znear;
  return p;
}

glm::dmat4 relative_view(const glm::dmat4& camera_world) {
  glm::dmat4 rotation = camera_world;
  rotation[3] = glm::dvec4(0, 0, 0, 1);
  return glm::inverse(rotation);
}

glm::dmat4 previous_relative_view_projection(const glm::dmat4& previous_world, const glm::dmat4& current_world,
                                             double yfov, double aspect, double znear) {
  const glm::dvec3 offset = glm::dvec3(current_world[3]) - glm::dvec3(previous_world[3]);
  return reversed_z_projection(yfov, aspect, znear) * relative_view(previous_world) *
         glm::translate(glm::dmat4(1.0), offset);
}

}  // namespace nightcap
