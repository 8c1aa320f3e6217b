#include "passes/core/frame_memory.h"

#include <limits>

#include "passes/core/aliasing.h"
#include "passes/core/execution_state.h"

namespace nightcap {

FrameMemory::~FrameMemory() {
  for (const GpuDevice::TransientBlock& block : blocks_) gpu_.return_transient_block(block);
}

void FrameMemory::place(const std::map<std::string, PhysicalResource*>& resources,
                        const std::map<std::string, Lifetime>& lifetimes, bool alias) {
  std::map<uint32_t, std::vector<MemoryNeed>> by_type;
  for (const auto& [name, r] : resources) {
    const GpuDevice::Placement p = r->desc.is_buffer ? gpu_.placement(r->buffer) : gpu_.placement(r->image);
    const Lifetime& lifetime = lifetimes.at(name);
    // Without aliasing every resource lives the whole frame, so none shares a byte.
    by_type[p.type].push_back({name, p.size, p.alignment, alias ? lifetime.first : 0,
                               alias ? lifetime.last : std::numeric_limits<int>::max()});
  }
  for (const auto& [type, needs] : by_type) {
    const MemoryPlan plan = plan_memory(needs);
    const GpuDevice::TransientBlock block =
        gpu_.take_transient_block(plan.bytes, type, "transient memory (type " + std::to_string(type) + ")");
    blocks_.push_back(block);
    bytes_ += plan.bytes;
    bytes_without_aliasing_ += plan.bytes_without_aliasing;
    for (const auto& [name, offset] : plan.offsets) {
      const PhysicalResource& r = *resources.at(name);
      if (r.desc.is_buffer)
        gpu_.bind(r.buffer, block.memory, offset);
      else
        gpu_.bind(r.image, block.memory, offset);
    }
    for (const auto& [name, previous] : plan.takes_over)
      for (const std::string& p : previous) {
        AccessState& wait = waits_[name];
        wait.stages |= lifetimes.at(p).last_use.stages;
        wait.access |= lifetimes.at(p).last_use.access;
      }
  }
}

}  // namespace nightcap
