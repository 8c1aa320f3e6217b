// The device memory of one frame's transient resources. Each is created unbound and placed by
// plan_memory (passes/core/aliasing.h) from its lifetime in the barrier plan, in one block per
// memory type, so resources alive at different steps of the frame share bytes (architecture.md:
// the graph aliases memory). A resource that takes over bytes waits, at its first use, for the
// last use of those it takes them from: waits() gives the executor what to add to that barrier.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "passes/core/device.h"
#include "passes/core/graph.h"

namespace nightcap {

struct PhysicalResource;

class FrameMemory {
 public:
  explicit FrameMemory(GpuDevice& gpu) : gpu_(gpu) {}
  // Returns the blocks to the device for a later frame: the resources in them must be destroyed,
  // and the frame's work done, first.
  ~FrameMemory();
  FrameMemory(const FrameMemory&) = delete;
  FrameMemory& operator=(const FrameMemory&) = delete;

  // Binds every resource (created unbound) into the blocks. `alias`: false gives each its own
  // bytes, to check that aliasing changes nothing.
  void place(const std::map<std::string, PhysicalResource*>& resources,
             const std::map<std::string, Lifetime>& lifetimes, bool alias);

  uint64_t bytes() const { return bytes_; }
  uint64_t bytes_without_aliasing() const { return bytes_without_aliasing_; }
  // Resource -> the last use of every resource whose bytes it takes over.
  const std::map<std::string, AccessState>& waits() const { return waits_; }

 private:
  GpuDevice& gpu_;
  std::vector<GpuDevice::TransientBlock> blocks_;
  uint64_t bytes_ = 0, bytes_without_aliasing_ = 0;
  std::map<std::string, AccessState> waits_;
};

}  // namespace nightcap
