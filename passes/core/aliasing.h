// Transient memory aliasing, planned from lifetimes alone so it can be unit-tested: resources
// whose lifetimes (the first to the last step of the frame that touches them) do not overlap may
// occupy the same bytes of one memory block (architecture.md: the graph aliases memory).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nightcap {

struct MemoryNeed {
  std::string resource;
  uint64_t size = 0, alignment = 1;  // as vkGet*MemoryRequirements says
  int first = 0, last = 0;           // steps of its first and last use, inclusive
};

struct MemoryPlan {
  std::map<std::string, uint64_t> offsets;  // into the block
  uint64_t bytes = 0;                       // the block's size
  uint64_t bytes_without_aliasing = 0;      // every resource in bytes of its own
  // Resource -> those whose bytes it takes over: its first use must wait for their last.
  std::map<std::string, std::vector<std::string>> takes_over;
};

// Largest first, each at the lowest aligned offset free of every resource alive at the same
// time. Throws std::invalid_argument for a need with last < first or a zero alignment.
MemoryPlan plan_memory(std::vector<MemoryNeed> needs);

}  // namespace nightcap
