#include "passes/frame/hierarchy.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "passes/core/graph.h"

namespace nightcap {
namespace {

float round_down(double v) {
  float f = float(v);
  return double(f) > v ? std::nextafter(f, -INFINITY) : f;
}

float round_up(double v) {
  float f = float(v);
  return double(f) < v ? std::nextafter(f, INFINITY) : f;
}

struct Builder {
  std::span<const Box> boxes;
  std::vector<uint32_t>& order;
  std::vector<HierarchyNode>& nodes;

  // Fills node `index` from order[first, first + count): a leaf when small, else two children
  // split at the median centre along the longest axis of the centres.
  void build(uint32_t index, uint32_t first, uint32_t count) {
    Box bounds{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
    Box centres = bounds;
    for (uint32_t k = first; k < first + count; ++k) {
      const Box& b = boxes[order[k]];
      bounds.min = glm::min(bounds.min, b.min);
      bounds.max = glm::max(bounds.max, b.max);
      const glm::dvec3 c = 0.5 * (b.min + b.max);
      centres.min = glm::min(centres.min, c);
      centres.max = glm::max(centres.max, c);
    }
    HierarchyNode& node = nodes[index];
    for (int k = 0; k < 3; ++k) {
      node.bounds_min[k] = round_down(bounds.min[k]);
      node.bounds_max[k] = round_up(bounds.max[k]);
    }
    if (count <= kLeafInstances) {
      node.first = first;
      node.count = count;
      return;
    }
    const glm::dvec3 spread = centres.max - centres.min;
    const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
    const uint32_t half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](uint32_t a, uint32_t b) {
                       const double ca = boxes[a].min[axis] + boxes[a].max[axis];
                       const double cb = boxes[b].min[axis] + boxes[b].max[axis];
                       return ca != cb ? ca < cb : a < b;
                     });
    const uint32_t children = uint32_t(nodes.size());
    nodes[index].first = children;
    nodes[index].count = 0;
    nodes.resize(nodes.size() + 2);
    build(children, first, half);
    build(children + 1, first + half, count - half);
  }
};

template <typename T>
std::span<const T> view(std::span<const uint8_t> bytes, size_t offset, size_t count) {
  return {reinterpret_cast<const T*>(bytes.data() + offset), count};
}

}  // namespace

Box transformed_box(const InstanceRecord& instance, const MeshRecord& mesh, const glm::dvec3& translation) {
  glm::dvec3 lo(mesh.bounds_min[0], mesh.bounds_min[1], mesh.bounds_min[2]);
  glm::dvec3 hi(mesh.bounds_max[0], mesh.bounds_max[1], mesh.bounds_max[2]);
  const glm::dvec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  glm::dvec3 world_centre = translation, extent(0.0);
  for (int c = 0; c < 3; ++c) {
    const glm::dvec3 axis(instance.basis[c * 3], instance.basis[c * 3 + 1], instance.basis[c * 3 + 2]);
    world_centre += axis * centre[c];
    extent += glm::abs(axis) * half[c];
  }
  // Rounding of the sums above is far below a millimetre; widen by a relative hair so the box
  // stays conservative.
  const glm::dvec3 slack = (glm::abs(world_centre) + extent) * 1e-12;
  return {world_centre - extent - slack, world_centre + extent + slack};
}

Box instance_box(const InstanceRecord& instance, std::span<const MeshRecord> meshes) {
  const glm::dvec3 translation(instance.position[0], instance.position[1], instance.position[2]);
  Box box{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
  int32_t mesh = int32_t(instance.primitive);
  for (size_t level = 0; mesh >= 0 && size_t(mesh) < meshes.size() && level < meshes.size(); ++level) {
    const Box b = transformed_box(instance, meshes[mesh], translation);
    box.min = glm::min(box.min, b.min);
    box.max = glm::max(box.max, b.max);
    mesh = meshes[mesh].coarser;
  }
  return box;
}

std::vector<uint8_t> build_hierarchy(std::span<const InstanceRecord> instances, std::span<const MeshRecord> meshes) {
  std::vector<Box> boxes(instances.size());
  std::vector<uint32_t> order, moving;
  for (uint32_t i = 0; i < instances.size(); ++i) {
    if (instances[i].flags & kInstanceMoving) {
      moving.push_back(i);
      continue;
    }
    boxes[i] = instance_box(instances[i], meshes);
    order.push_back(i);
  }
  std::vector<HierarchyNode> nodes(1);
  if (!order.empty()) {
    nodes.reserve(2 * (order.size() / kLeafInstances + 1) + 1);
    Builder{boxes, order, nodes}.build(0, 0, uint32_t(order.size()));
  }
  const HierarchyHeader header{uint32_t(nodes.size()), uint32_t(order.size()), uint32_t(moving.size()), 0};
  std::vector<uint8_t> bytes(sizeof(header) + nodes.size() * sizeof(HierarchyNode) +
                             (order.size() + moving.size()) * 4);
  uint8_t* out = bytes.data();
  std::memcpy(out, &header, sizeof(header));
  out += sizeof(header);
  std::memcpy(out, nodes.data(), nodes.size() * sizeof(HierarchyNode));
  out += nodes.size() * sizeof(HierarchyNode);
  if (!order.empty()) std::memcpy(out, order.data(), order.size() * 4);
  out += order.size() * 4;
  if (!moving.empty()) std::memcpy(out, moving.data(), moving.size() * 4);
  return bytes;
}

Hierarchy Hierarchy::parse(std::span<const uint8_t> bytes, size_t instance_count) {
  auto fail = [](const std::string& what) { throw GraphError("scene.hierarchy: " + what); };
  HierarchyHeader header;
  if (bytes.size() < sizeof(header)) fail("no header");
  std::memcpy(&header, bytes.data(), sizeof(header));
  const uint64_t expected = sizeof(header) + uint64_t(header.node_count) * sizeof(HierarchyNode) +
                            (uint64_t(header.static_count) + header.moving_count) * 4;
  if (header.node_count == 0 || expected != bytes.size())
    fail("its header does not match its size (" + std::to_string(bytes.size()) + " bytes)");
  if (uint64_t(header.static_count) + header.moving_count > instance_count)
    fail("lists more instances than scene.instances holds");
  Hierarchy h;
  size_t offset = sizeof(header);
  h.nodes = view<HierarchyNode>(bytes, offset, header.node_count);
  offset += header.node_count * sizeof(HierarchyNode);
  h.static_order = view<uint32_t>(bytes, offset, header.static_count);
  offset += header.static_count * 4;
  h.moving = view<uint32_t>(bytes, offset, header.moving_count);
  for (uint32_t i : h.static_order)
    if (i >= instance_count) fail("instance " + std::to_string(i) + " is out of range");
  for (uint32_t i : h.moving)
    if (i >= instance_count) fail("instance " + std::to_string(i) + " is out of range");
  // Children always come after their parent, so a walk ends; leaves stay within the order.
  for (uint32_t n = 0; n < h.nodes.size(); ++n) {
    const HierarchyNode& node = h.nodes[n];
    if (node.count == 0 && header.static_count > 0) {
      if (node.first <= n || uint64_t(node.first) + 1 >= h.nodes.size())
        fail("node " + std::to_string(n) + " has bad children");
    } else if (uint64_t(node.first) + node.count > header.static_count) {
      fail("leaf " + std::to_string(n) + " points past the instance order");
    }
  }
  return h;
}

}  // namespace nightcap
