// Levels of detail (frame.md): an instance draws the finest level of its mesh out to that level's
// lod_distance, then the next coarser one, and so on, each judged by the distance from the
// viewpoint (the camera, a probe) to the centre of the finest level's box; nothing past the
// chosen level's draw_distance. cull.main, shadow.cull and probes.cull choose by this rule.
#pragma once

#include <glm/glm.hpp>

#include <string>

#include "passes/core/graph.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

// The centre of a mesh's box under `model`.
inline glm::dvec3 box_centre(const glm::dmat4& model, const MeshRecord& mesh) {
  return glm::dvec3(model * glm::dvec4(0.5 * (mesh.bounds_min[0] + mesh.bounds_max[0]),
                                       0.5 * (mesh.bounds_min[1] + mesh.bounds_max[1]),
                                       0.5 * (mesh.bounds_min[2] + mesh.bounds_max[2]), 1.0));
}

struct LevelOfDetail {
  const MeshRecord* mesh;
  uint32_t steps;  // from the finest
  bool drawn;      // within the level's draw distance
};

// The level `distance` metres from the viewpoint, starting from `finest`. `mesh_at(index)` looks
// up a coarser level as the pass checks a mesh index; a chain longer than `mesh_count` loops,
// a GraphError naming `pass`.
template <class MeshAt>
LevelOfDetail level_of_detail(const MeshRecord& finest, double distance, size_t mesh_count, const std::string& pass,
                              MeshAt mesh_at) {
  const MeshRecord* mesh = &finest;
  uint32_t steps = 0;
  while (mesh->coarser >= 0 && distance > mesh->lod_distance) {
    if (++steps > mesh_count) throw GraphError(pass + ": mesh levels of detail form a cycle");
    mesh = mesh_at(uint32_t(mesh->coarser));
  }
  return {mesh, steps, distance <= mesh->draw_distance};
}

}  // namespace nightcap
