#include "passes/core/aliasing.h"

#include <algorithm>
#include <stdexcept>

namespace nightcap {
namespace {

uint64_t align_up(uint64_t value, uint64_t alignment) { return (value + alignment - 1) / alignment * alignment; }

bool lifetimes_overlap(const MemoryNeed& a, const MemoryNeed& b) { return a.first <= b.last && b.first <= a.last; }

}  // namespace

MemoryPlan plan_memory(std::vector<MemoryNeed> needs) {
  for (const MemoryNeed& n : needs) {
    if (n.last < n.first) throw std::invalid_argument(n.resource + ": last use before first use");
    if (n.alignment == 0) throw std::invalid_argument(n.resource + ": zero alignment");
  }
  // Largest first packs best; ties in frame order, then by name, so the plan is deterministic.
  std::sort(needs.begin(), needs.end(), [](const MemoryNeed& a, const MemoryNeed& b) {
    if (a.size != b.size) return a.size > b.size;
    if (a.first != b.first) return a.first < b.first;
    return a.resource < b.resource;
  });
  MemoryPlan plan;
  struct Placed {
    const MemoryNeed* need;
    uint64_t offset;
  };
  std::vector<Placed> placed;
  for (const MemoryNeed& need : needs) {
    plan.bytes_without_aliasing = align_up(plan.bytes_without_aliasing, need.alignment) + need.size;
    // Byte ranges taken by resources alive at the same time, in address order.
    std::vector<std::pair<uint64_t, uint64_t>> taken;
    for (const Placed& p : placed)
      if (lifetimes_overlap(*p.need, need)) taken.push_back({p.offset, p.offset + p.need->size});
    std::sort(taken.begin(), taken.end());
    uint64_t offset = 0;
    for (const auto& [begin, end] : taken) {
      if (align_up(offset, need.alignment) + need.size <= begin) break;
      offset = std::max(offset, end);
    }
    offset = align_up(offset, need.alignment);
    placed.push_back({&need, offset});
    plan.offsets[need.resource] = offset;
    plan.bytes = std::max(plan.bytes, offset + need.size);
  }
  for (const Placed& a : placed)
    for (const Placed& b : placed) {
      const bool bytes_overlap = a.offset < b.offset + b.need->size && b.offset < a.offset + a.need->size;
      if (&a != &b && bytes_overlap && b.need->last < a.need->first)
        plan.takes_over[a.need->resource].push_back(b.need->resource);
    }
  return plan;
}

}  // namespace nightcap
