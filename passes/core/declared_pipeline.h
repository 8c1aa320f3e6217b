// The pipeline a pass's declaration implies, so that no pass states a fact twice: shaders from
// its `.shader()` paths, descriptor set 0 from its bindable uses, attachment formats from its
// outputs, push-constant size from its typed constants, fixed-function state as declared.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "passes/core/pass.h"
#include "passes/core/pipeline_cache.h"

namespace nightcap {

// One descriptor of set 0, as PassContext::push writes it.
struct Binding {
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  std::string resource;
  VkSampler sampler = VK_NULL_HANDLE;
  ViewAspect aspect = ViewAspect::natural;
  int mip = -1;  // -1: every mip
  uint64_t offset = 0, range = VK_WHOLE_SIZE;
  int layer = -1;  // -1: every layer (an array, cube or 3D view); else that layer as a 2D image

  static Binding uniform(uint32_t b, std::string r) { return {b, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, std::move(r)}; }
  static Binding storage(uint32_t b, std::string r, uint64_t offset = 0, uint64_t range = VK_WHOLE_SIZE) {
    Binding x{b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::move(r)};
    x.offset = offset;
    x.range = range;
    return x;
  }
  static Binding texture(uint32_t b, std::string r, VkSampler s, ViewAspect a = ViewAspect::natural, int mip = -1,
                         int layer = -1) {
    return {b, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, std::move(r), s, a, mip, 0, VK_WHOLE_SIZE, layer};
  }
  static Binding image(uint32_t b, std::string r, int mip = 0, int layer = -1) {
    return {b,
            VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
            std::move(r),
            VK_NULL_HANDLE,
            ViewAspect::natural,
            mip,
            0,
            VK_WHOLE_SIZE,
            layer};
  }
};

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
// The GLSL preamble that numbers the slots: shaders write `binding = NC_BINDING(name)` (plus k
// for a use's k-th binding), where name is the use's ResourceUse::shader_name(), so no shader
// repeats the declaration's order. A name the pass does not declare fails the shader's compile,
// naming NC_BINDING_<name>; so does a name two uses share (a resource read and written: name
// one with PassDecl::as), on an identifier that says so.
std::string binding_defines(const PassDecl& decl, const DescOf& desc_of);
// What each declared slot binds: uniform and storage buffers whole; a sampled image through its
// declared sampler (made by `sampler_of`) at its declared aspects, at the one mip and layer its
// range selects or all of them; a storage image at its range's first mip; an image declared with
// level_mips at `level` plus each offset. A history input binds previous(resource). A prefix
// read's textures change per draw (PassContext::push_draw_textures): it is left out here.
std::vector<Binding> declared_bindings(const PassDecl& decl, const DescOf& desc_of,
                                       const std::function<VkSampler(const SamplerDesc&)>& sampler_of,
                                       std::optional<uint32_t> level = std::nullopt);
// The one prefix read a pass binds per draw (its slot), or throws.
DeclaredSlot prefix_slot(const PassDecl& decl, const DescOf& desc_of);
// The sampler of a sampled use that declares none: each texel as stored, nothing past the edge.
SamplerDesc nearest_clamp_sampler();
// Bilinear between the four nearest texels of the base level, clamped to the edge.
SamplerDesc bilinear_clamp_sampler();
SamplerDesc trilinear_clamp_sampler();  // bilinear, and linear between mips
// The colour attachments in declaration order, and the depth attachment ("" when none).
std::vector<std::string> colour_targets(const PassDecl& decl);
std::string depth_target(const PassDecl& decl);

GraphicsPipelineDesc declared_graphics_pipeline(const PassDecl& decl, const DescOf& desc_of);
ComputePipelineDesc declared_compute_pipeline(const PassDecl& decl, const DescOf& desc_of);

}  // namespace nightcap
