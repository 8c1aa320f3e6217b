// The memory aliasing plan: resources alive at the same time never share a byte, resources that
// are not may, every offset is aligned, and a resource that takes over bytes knows whose.
#include <gtest/gtest.h>

#include <random>

#include "passes/core/aliasing.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

bool bytes_overlap(const MemoryPlan& plan, const MemoryNeed& a, const MemoryNeed& b) {
  const uint64_t x = plan.offsets.at(a.resource), y = plan.offsets.at(b.resource);
  return x < y + b.size && y < x + a.size;
}

TEST(Aliasing, ResourcesAliveApartShareMemory) {
  // a (steps 0-1) and c (3-4) never live together: c takes a's bytes; b lives across both.
  const std::vector<MemoryNeed> needs{{"a", 1000, 256, 0, 1}, {"b", 500, 256, 1, 3}, {"c", 1000, 256, 3, 4}};
  const MemoryPlan plan = plan_memory(needs);
  EXPECT_EQ(plan.offsets.at("a"), plan.offsets.at("c"));
  EXPECT_FALSE(bytes_overlap(plan, needs[0], needs[1]));
  EXPECT_FALSE(bytes_overlap(plan, needs[1], needs[2]));
  EXPECT_EQ(plan.bytes, 1024u + 500u);
  EXPECT_EQ(plan.bytes_without_aliasing, 1024u + 1024u + 500u);  // a, c, b: largest first, aligned
  EXPECT_EQ(plan.takes_over.at("c"), std::vector<std::string>{"a"});
  EXPECT_FALSE(plan.takes_over.count("a"));
  EXPECT_FALSE(plan.takes_over.count("b"));
}

TEST(Aliasing, OffsetsRespectEachAlignment) {
  const MemoryPlan plan = plan_memory({{"small", 3, 1, 0, 5}, {"aligned", 64, 4096, 0, 5}, {"odd", 7, 16, 0, 5}});
  EXPECT_EQ(plan.offsets.at("aligned") % 4096, 0u);
  EXPECT_EQ(plan.offsets.at("odd") % 16, 0u);
}

TEST(Aliasing, MistakesAreRefused) {
  EXPECT_THROW(plan_memory({{"backwards", 16, 16, 3, 2}}), std::invalid_argument);
  EXPECT_THROW(plan_memory({{"unaligned", 16, 0, 0, 1}}), std::invalid_argument);
}

TEST(Aliasing, RandomFramesNeverOverlapLiveResources) {
  // Stress: 300 random lifetimes and sizes; the plan is valid, no larger than keeping every
  // resource apart, and no smaller than the most memory alive at any one step.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<MemoryNeed> needs;
    for (int i = 0; i < 300; ++i) {
      const int first = int(rng() % 60), last = first + int(rng() % 12);
      needs.push_back({"r" + std::to_string(i), 1 + rng() % 100000, uint64_t(1) << (rng() % 13), first, last});
    }
    const MemoryPlan plan = plan_memory(needs);
    uint64_t peak_alive = 0;
    for (int step = 0; step < 72; ++step) {
      uint64_t alive = 0;
      for (const MemoryNeed& n : needs) alive += n.first <= step && step <= n.last ? n.size : 0;
      peak_alive = std::max(peak_alive, alive);
    }
    for (size_t i = 0; i < needs.size(); ++i) {
      EXPECT_EQ(plan.offsets.at(needs[i].resource) % needs[i].alignment, 0u);
      EXPECT_LE(plan.offsets.at(needs[i].resource) + needs[i].size, plan.bytes);
      for (size_t j = i + 1; j < needs.size(); ++j) {
        const bool alive_together = needs[i].first <= needs[j].last && needs[j].first <= needs[i].last;
        if (alive_together) {
          ASSERT_FALSE(bytes_overlap(plan, needs[i], needs[j])) << trial << ": " << i << ", " << j;
        }
      }
    }
    EXPECT_GE(plan.bytes, peak_alive);
    EXPECT_LE(plan.bytes, plan.bytes_without_aliasing);
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
