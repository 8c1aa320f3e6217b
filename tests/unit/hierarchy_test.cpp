// scene.hierarchy (passes/frame/hierarchy.h) on the 2 km map: every static instance sits in
// exactly one leaf, every moving one in the moving list, every node's box holds its children's
// boxes and every instance's box (all its levels of detail) lies in its leaf's box; a corrupt
// hierarchy (truncated, a child pointing back up, an instance out of range) is refused with a
// message naming scene.hierarchy.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "passes/core/graph.h"
#include "passes/frame/hierarchy.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

bool contains(const HierarchyNode& n, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (b.min[k] < n.bounds_min[k] || b.max[k] > n.bounds_max[k]) return false;
  return true;
}

TEST(Hierarchy, HoldsEveryInstanceOnceInBoxesThatContainIt) {
  const Scene scene = build_map({5, 2.0, Shot::street});
  const Imports imports = scene_imports(scene);
  const auto instances = host_records<InstanceRecord>(*imports.at("scene.instances").bytes);
  const auto meshes = host_records<MeshRecord>(*imports.at("scene.meshes").bytes);
  const auto& bytes = *imports.at("scene.hierarchy").bytes;
  const Hierarchy h = Hierarchy::parse(bytes, instances.size());
  std::set<uint32_t> seen;
  size_t leaves = 0;
  for (uint32_t n = 0; n < h.nodes.size(); ++n) {
    const HierarchyNode& node = h.nodes[n];
    if (node.count == 0) {
      for (uint32_t c : {node.first, node.first + 1}) {
        const HierarchyNode& child = h.nodes[c];
        EXPECT_TRUE(contains(node, {{child.bounds_min[0], child.bounds_min[1], child.bounds_min[2]},
                                    {child.bounds_max[0], child.bounds_max[1], child.bounds_max[2]}}))
            << "node " << c << " outside its parent " << n;
      }
      continue;
    }
    ++leaves;
    EXPECT_LE(node.count, kLeafInstances);
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const uint32_t i = h.static_order[k];
      EXPECT_TRUE(seen.insert(i).second) << "instance " << i << " in two leaves";
      EXPECT_TRUE(contains(node, instance_box(instances[i], meshes))) << "instance " << i << " outside its leaf";
      EXPECT_FALSE(instances[i].flags & kInstanceMoving);
    }
  }
  for (uint32_t i : h.moving) {
    EXPECT_TRUE(instances[i].flags & kInstanceMoving);
    EXPECT_TRUE(seen.insert(i).second);
  }
  EXPECT_EQ(seen.size(), instances.size());
  EXPECT_GT(leaves, instances.size() / kLeafInstances / 2);
}

TEST(Hierarchy, CorruptHierarchiesAreRefused) {
  const Scene scene = build_map({5, 0.5, Shot::street});
  const Imports imports = scene_imports(scene);
  const size_t count = scene.instances.size();
  const std::vector<uint8_t> good = *imports.at("scene.hierarchy").bytes;
  ASSERT_NO_THROW(Hierarchy::parse(good, count));
  auto refused = [&](std::vector<uint8_t> bytes, const std::string& what) {
    try {
      Hierarchy::parse(bytes, count);
    } catch (const GraphError& e) {
      EXPECT_NE(std::string(e.what()).find("scene.hierarchy"), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << what << " was accepted";
  };
  refused({good.begin(), good.end() - 4}, "a truncated hierarchy");
  refused({good.begin(), good.begin() + 8}, "a header alone");
  std::vector<uint8_t> cycle = good;
  HierarchyNode root;
  std::memcpy(&root, cycle.data() + sizeof(HierarchyHeader), sizeof(root));
  ASSERT_EQ(root.count, 0u);
  root.first = 0;  // the root's children would be itself
  std::memcpy(cycle.data() + sizeof(HierarchyHeader), &root, sizeof(root));
  refused(cycle, "a cycle");
  std::vector<uint8_t> outside = good;
  const uint32_t huge = uint32_t(count + 7);
  std::memcpy(outside.data() + outside.size() - 4, &huge, 4);
  refused(outside, "an instance out of range");
  EXPECT_THROW(Hierarchy::parse(good, count / 2), GraphError);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
