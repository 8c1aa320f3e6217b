// Pipelines, samplers and layouts built from the pipeline descriptions passes give, kept per
// device across frames and replays.
#pragma once

#include <vulkan/vulkan.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "passes/core/device.h"
#include "passes/core/pipeline_state.h"
#include "passes/core/sampler.h"

namespace nightcap {

struct GraphicsPipelineDesc {
  std::string vertex, fragment;            // shader paths; no fragment shader: depth only
  std::vector<VkDescriptorType> bindings;  // set 0, binding i (push descriptors)
  uint32_t push_constant_bytes = 0;
  std::vector<VkFormat> color_formats;
  std::vector<BlendState> blend;  // parallel to color_formats; missing ones do not blend
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  RasterState raster;
  DepthStencilState depth_stencil;
  std::vector<int32_t> specialization;  // constant_id i = value
};

struct ComputePipelineDesc {
  std::string shader;
  std::vector<VkDescriptorType> bindings;
  uint32_t push_constant_bytes = 0;
  std::vector<int32_t> specialization;
};

// The state a pipeline or sampler was built with, in Vulkan's names, as the capture records it.
nlohmann::json describe(const GraphicsPipelineDesc& desc);
nlohmann::json describe(const ComputePipelineDesc& desc);
nlohmann::json describe(const SamplerDesc& desc);

// SPIR-V for a pass's shader: the recorded code, an override, or the built-in source compiled
// with `bindings`, the preamble that numbers the pass's declared slots (binding_defines).
using ShaderProvider =
    std::function<std::vector<uint32_t>(const std::string& pass, const std::string& path, const std::string& bindings)>;

// Pipelines, samplers and layouts survive across frames and replays on one device.
class PipelineCache {
 public:
  explicit PipelineCache(GpuDevice& gpu) : gpu_(gpu) {}
  ~PipelineCache();
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  struct Entry {
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  };
  const Entry& graphics(const GraphicsPipelineDesc& desc, const std::vector<uint32_t>& vs,
                        const std::vector<uint32_t>& fs);
  const Entry& compute(const ComputePipelineDesc& desc, const std::vector<uint32_t>& cs);
  VkSampler sampler(const SamplerDesc& desc);

 private:
  VkShaderModule module(const std::vector<uint32_t>& code, const std::string& path);
  // `pipeline`: the name of the pipeline the layouts are made for; they are named after it.
  std::pair<VkDescriptorSetLayout, VkPipelineLayout> layout(const std::vector<VkDescriptorType>& bindings,
                                                            uint32_t push_bytes, const std::string& pipeline);
  GpuDevice& gpu_;
  std::map<std::string, Entry> pipelines_;
  std::map<std::string, VkSampler> samplers_;
  std::vector<VkShaderModule> modules_;
};

}  // namespace nightcap
