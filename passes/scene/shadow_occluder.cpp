#include "passes/scene/shadow_occluder.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace nightcap {
namespace {

glm::dvec3 vertex_position(const Scene& scene, const Primitive& p, uint32_t k) {
  const Vertex& v = scene.vertices.at(size_t(int64_t(scene.indices.at(p.first_index + k)) + p.vertex_offset));
  return {v.position[0], v.position[1], v.position[2]};
}

}  // namespace

uint32_t shadow_occluder_indices(const Scene& scene, uint32_t index) {
  const Instance& instance = scene.instances.at(index);
  const Material& material = scene.materials.at(scene.material_of(instance));
  const double determinant = glm::determinant(glm::dmat3(instance.world));
  if (instance.moving || material.decal || material.alpha_mode != AlphaMode::opaque || !std::isfinite(determinant) ||
      determinant == 0.0)
    return 0;
  const Primitive& finest = scene.primitives.at(instance.primitive);
  const uint32_t prefix = std::min(finest.occluder_index_count, finest.index_count) / 3 * 3;
  uint32_t levels = 0;
  for (int32_t level = int32_t(instance.primitive); level >= 0; level = scene.primitives.at(uint32_t(level)).coarser) {
    if (++levels > scene.primitives.size()) return 0;  // a cycle of levels
    const Primitive& p = scene.primitives.at(uint32_t(level));
    if (!std::isinf(p.draw_distance) || std::min(p.occluder_index_count, p.index_count) / 3 * 3 != prefix) return 0;
    for (uint32_t k = 0; k < prefix; ++k)
      if (glm::length(vertex_position(scene, p, k) - vertex_position(scene, finest, k)) >= 1e-3) return 0;
  }
  return prefix;
}

}  // namespace nightcap
