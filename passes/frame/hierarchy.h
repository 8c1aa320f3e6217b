// scene.hierarchy: a bounding-volume hierarchy over the static instances, built once when the
// scene becomes graph imports, so cull.main visits the few nodes a view can see instead of every
// instance of a 16 km map each frame. Moving instances are listed apart: their boxes change
// every frame and cull.main tests them one by one.
//
// Layout: HierarchyHeader, then node_count HierarchyNode, then the static instance indices in
// leaf order, then the moving instance indices.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "passes/frame/scene_resources.h"

namespace nightcap {

struct HierarchyHeader {
  uint32_t node_count, static_count, moving_count, pad;
};

// World-space box at time 0, rounded outward to float. A leaf (count > 0) holds the static
// instances order[first, first + count); an inner node (count == 0) has children first and
// first + 1. Node 0 is the root.
struct HierarchyNode {
  float bounds_min[3];
  uint32_t first;
  float bounds_max[3];
  uint32_t count;
};
static_assert(sizeof(HierarchyNode) == 32);

constexpr uint32_t kLeafInstances = 8;

struct Box {
  glm::dvec3 min{0.0}, max{0.0};
};

// The instance's world box at time 0 around every level of detail of its mesh.
Box instance_box(const InstanceRecord& instance, std::span<const MeshRecord> meshes);
// The world box of `mesh` under the instance's basis with its translation at `translation`.
Box transformed_box(const InstanceRecord& instance, const MeshRecord& mesh, const glm::dvec3& translation);

std::vector<uint8_t> build_hierarchy(std::span<const InstanceRecord> instances, std::span<const MeshRecord> meshes);

// A parsed scene.hierarchy whose every index has been checked against the instance count and
// whose tree has no cycle; throws GraphError naming the problem.
struct Hierarchy {
  std::span<const HierarchyNode> nodes;
  std::span<const uint32_t> static_order, moving;

  static Hierarchy parse(std::span<const uint8_t> bytes, size_t instance_count);
};

}  // namespace nightcap
