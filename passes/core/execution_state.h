// What the executor and the pass contexts it hands out share while a graph runs: the physical
// resources with their synchronisation state, host data, and the pass being recorded. Internal
// to passes/core.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "passes/core/context.h"
#include "passes/core/executor.h"

namespace nightcap {

struct PhysicalResource {
  ResourceDesc desc;
  GpuImage image;
  GpuBuffer buffer;
  std::map<std::tuple<int, int, int>, VkImageView> views;  // (aspect, mip, layer) -> view
  int version = -1;                                        // current version index
  bool owned = true;  // false: a history slot's image or buffer, which the pool destroys
};

struct PassContext::Shared {
  GpuDevice& gpu;
  PipelineCache& cache;
  const ShaderProvider& shaders;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  std::map<std::string, PhysicalResource> resources;
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> host;
  std::map<std::string, std::vector<uint8_t>> cpu_outputs;
  PassExecution* current = nullptr;
};

inline bool is_depth(const ResourceDesc& d) { return !d.is_buffer && format_info(d.format)->is_depth; }

inline VkImageAspectFlags natural_aspects(VkFormat format) {
  const FormatInfo f = *format_info(format);
  if (f.has_stencil) return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
  return f.is_depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

}  // namespace nightcap
