// The pipeline a pass's declaration implies, so that no pass states a fact twice: shaders from
// its `.shader()` paths, descriptor set 0 from its bindable uses, attachment formats from its
// outputs, push-constant size from its typed constants, fixed-function state as declared.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "passes/core/pass.h"
#include "passes/core/pipeline_cache.h"

namespace nightcap {

// A use's bindings in set 0: `count` from binding `first`, all of `type`.
struct DeclaredSlot {
  const ResourceUse* use = nullptr;
  uint32_t first = 0, count = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
};

// The resolved description of a resource the pass uses (formats of modified outputs and
// whether a storage use is a buffer are known only once the graph is compiled).
using DescOf = std::function<const ResourceDesc&(const std::string& resource)>;

// Inputs, then outputs, in declaration order (PassDecl::slots).
std::vector<DeclaredSlot> declared_slots(const PassDecl& decl, const DescOf& desc_of);
std::vector<VkDescriptorType> declared_layout(const PassDecl& decl, const DescOf& desc_of);
// The colour attachments in declaration order, and the depth attachment ("" when none).
std::vector<std::string> colour_targets(const PassDecl& decl);
std::string depth_target(const PassDecl& decl);

GraphicsPipelineDesc declared_graphics_pipeline(const PassDecl& decl, const DescOf& desc_of);
ComputePipelineDesc declared_compute_pipeline(const PassDecl& decl, const DescOf& desc_of);

}  // namespace nightcap
