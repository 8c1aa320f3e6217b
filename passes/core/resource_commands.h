// The Vulkan commands recorded on a frame's physical resources (execution_state.h) by the
// executor and the pass contexts: creating one, issuing the plan's barriers, clears, whole
// copies, and the regions of a raw transfer between an image and the host's bytes. Internal to
// passes/core.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "passes/core/execution_state.h"

namespace nightcap {

// The image usage a use of a resource needs (none for a buffer's uses or the host's).
VkImageUsageFlags usage_for(Use use);

// Creates the image or buffer of `r.desc`: with its own memory, or unbound for FrameMemory.
void create_resource(GpuDevice& gpu, const std::string& name, PhysicalResource& r, VkImageUsageFlags usage, bool bound);

// Every aspect and mip of an image (all its layers), each at its raw_subresource_offset in the
// host's bytes.
std::vector<VkBufferImageCopy> raw_copy_regions(const ResourceDesc& d);

// Every mip, layer and aspect of `from` into `to` (same description), both in transfer states.
void copy_whole(VkCommandBuffer cmd, const PhysicalResource& from, const PhysicalResource& to);

// Issues barriers of the graph's plan as one dependency.
// `waits`: a resource's first-use barriers also wait for the last use of the resources whose
// memory it takes over (FrameMemory::waits).
void issue(VkCommandBuffer cmd, std::map<std::string, PhysicalResource>& resources,
           const std::vector<PlannedBarrier>& planned, const std::map<std::string, AccessState>& waits);

// The contents a resource has when nothing computed it: its declared clear value (zero for a
// buffer), here for `range`. It must be in the transfer-destination state.
// A buffer is filled with zeros whatever `value` says: its only clear.
void clear_to(VkCommandBuffer cmd, const PhysicalResource& r, const Subresources& range, const VkClearValue& value);

}  // namespace nightcap
