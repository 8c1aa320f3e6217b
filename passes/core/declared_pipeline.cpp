#include "passes/core/declared_pipeline.h"

#include <algorithm>
#include <map>

#include "passes/core/graph.h"

namespace nightcap {
namespace {

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The pass's one shader of a stage ("" when it has none); two would leave the pipeline ambiguous.
std::string stage_shader(const PassDecl& decl, const std::string& extension) {
  std::string found;
  for (const std::string& path : decl.shaders)
    if (ends_with(path, extension)) {
      if (!found.empty()) throw GraphError(decl.name + ": declares two " + extension + " shaders");
      found = path;
    }
  return found;
}

// The one mip or layer a declared range selects, or -1 for all of them.
int single(uint32_t base, uint32_t count) { return count == 1 ? int(base) : -1; }

}  // namespace

std::vector<DeclaredSlot> declared_slots(const PassDecl& decl, const DescOf& desc_of) {
  std::vector<DeclaredSlot> slots;
  uint32_t next = 0;
  for (const std::vector<ResourceUse>* uses : {&decl.inputs, &decl.outputs})
    for (const ResourceUse& use : *uses) {
      DeclaredSlot slot{&use, next, use.slots};
      switch (use.use) {
        case Use::uniform_buffer:
          slot.type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
          break;
        case Use::sampled:
          slot.type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
          break;
        case Use::storage_read:
        case Use::storage_write: {
          if (use.prefix) throw GraphError(decl.name + ": a prefix read is bound as sampled images only");
          const bool buffer = use.is_buffer || desc_of(use.resource).is_buffer;
          slot.type = buffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
          break;
        }
        default:
          continue;  // attachments, index buffers and host data are not descriptors
      }
      if (slot.count == 0) continue;
      slots.push_back(slot);
      next += slot.count;
    }
  return slots;
}

std::vector<VkDescriptorType> declared_layout(const PassDecl& decl, const DescOf& desc_of) {
  std::vector<VkDescriptorType> layout;
  for (const DeclaredSlot& slot : declared_slots(decl, desc_of)) layout.insert(layout.end(), slot.count, slot.type);
  return layout;
}

std::string binding_defines(const PassDecl& decl, const DescOf& desc_of) {
  const std::vector<DeclaredSlot> slots = declared_slots(decl, desc_of);
  std::map<std::string, int> uses;
  for (const DeclaredSlot& slot : slots) ++uses[slot.use->shader_name()];
  std::string defines = "#define NC_BINDING(name) NC_BINDING_##name\n";
  for (const DeclaredSlot& slot : slots) {
    const std::string name = slot.use->shader_name();
    // A name two uses share stands for neither: a shader that writes it fails to compile on an
    // identifier that says why.
    const std::string value =
        uses[name] == 1 ? std::to_string(slot.first) : name + "_is_bound_twice_name_one_use_with_as";
    defines += "#define NC_BINDING_" + name + " " + value + "\n";
  }
  return defines;
}

std::vector<Binding> declared_bindings(const PassDecl& decl, const DescOf& desc_of,
                                       const std::function<VkSampler(const SamplerDesc&)>& sampler_of,
                                       std::optional<uint32_t> level) {
  std::vector<Binding> bindings;
  for (const DeclaredSlot& slot : declared_slots(decl, desc_of)) {
    const ResourceUse& use = *slot.use;
    if (use.prefix) continue;
    const std::string name = use.bound_name();
    const int layer = single(use.range.base_layer, use.range.layer_count);
    // The mip of each binding: one the range selects (or all: -1), or one per declared offset.
    std::vector<int> mips(slot.count, single(use.range.base_mip, use.range.mip_count));
    if (!use.level_mips.empty()) {
      if (!level)
        throw GraphError(decl.name + ": '" + use.resource + "' is bound per level: push_declared(level) names it");
      for (uint32_t i = 0; i < slot.count; ++i) mips[i] = std::max(0, int(*level) + use.level_mips[i]);
    }
    if (slot.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) {
      std::vector<ViewAspect> aspects = use.aspects;
      if (aspects.empty()) aspects.assign(slot.count, ViewAspect::natural);
      if (aspects.size() != slot.count)
        throw GraphError(decl.name + ": '" + use.resource + "' takes more bindings than its declared aspects");
      const VkSampler sampler = sampler_of(use.sampler.value_or(nearest_clamp_sampler()));
      for (uint32_t i = 0; i < slot.count; ++i)
        bindings.push_back(Binding::texture(slot.first + i, name, sampler, aspects[i], mips[i], layer));
      continue;
    }
    if (slot.type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) {
      for (uint32_t i = 0; i < slot.count; ++i)
        bindings.push_back(
            Binding::image(slot.first + i, name, use.level_mips.empty() ? int(use.range.base_mip) : mips[i], layer));
      continue;
    }
    if (slot.count != 1)
      throw GraphError(decl.name + ": buffer '" + use.resource + "' takes one binding, not " +
                       std::to_string(slot.count));
    bindings.push_back(slot.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER ? Binding::uniform(slot.first, name)
                                                                      : Binding::storage(slot.first, name));
  }
  return bindings;
}

DeclaredSlot prefix_slot(const PassDecl& decl, const DescOf& desc_of) {
  std::optional<DeclaredSlot> found;
  for (const DeclaredSlot& slot : declared_slots(decl, desc_of))
    if (slot.use->prefix) {
      if (found) throw GraphError(decl.name + ": binds two prefix reads per draw; one is supported");
      found = slot;
    }
  if (!found) throw GraphError(decl.name + ": binds textures per draw but declares no prefix read (read_all)");
  return *found;
}

SamplerDesc nearest_clamp_sampler() {
  SamplerDesc desc;
  desc.mag_filter = desc.min_filter = VK_FILTER_NEAREST;
  desc.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  desc.wrap_u = desc.wrap_v = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  return desc;
}

SamplerDesc bilinear_clamp_sampler() {
  SamplerDesc desc = nearest_clamp_sampler();
  desc.mag_filter = desc.min_filter = VK_FILTER_LINEAR;
  return desc;
}

SamplerDesc trilinear_clamp_sampler() {
  SamplerDesc desc = bilinear_clamp_sampler();
  desc.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  return desc;
}

std::vector<std::string> colour_targets(const PassDecl& decl) {
  std::vector<std::string> targets;
  for (const ResourceUse& out : decl.outputs)
    if (out.use == Use::color_attachment) targets.push_back(out.resource);
  return targets;
}

std::string depth_target(const PassDecl& decl) {
  for (const std::vector<ResourceUse>* uses : {&decl.outputs, &decl.inputs})
    for (const ResourceUse& use : *uses)
      if (use.use == Use::depth_attachment) return use.resource;
  return "";
}

GraphicsPipelineDesc declared_graphics_pipeline(const PassDecl& decl, const DescOf& desc_of) {
  GraphicsPipelineDesc desc;
  desc.vertex = stage_shader(decl, ".vert");
  if (desc.vertex.empty()) throw GraphError(decl.name + ": a graphics pass needs a .vert shader");
  desc.fragment = stage_shader(decl, ".frag");
  desc.bindings = declared_layout(decl, desc_of);
  desc.push_constant_bytes = decl.push_constant_bytes;
  for (const std::string& target : colour_targets(decl)) {
    desc.color_formats.push_back(desc_of(target).format);
    auto blend = decl.blend_states.find(target);
    desc.blend.push_back(blend == decl.blend_states.end() ? BlendState{} : blend->second);
  }
  const std::string depth = depth_target(decl);
  if (!depth.empty()) desc.depth_format = desc_of(depth).format;
  desc.raster = decl.raster_state;
  desc.depth_stencil = decl.depth_stencil_state;
  return desc;
}

ComputePipelineDesc declared_compute_pipeline(const PassDecl& decl, const DescOf& desc_of) {
  ComputePipelineDesc desc;
  desc.shader = stage_shader(decl, ".comp");
  if (desc.shader.empty()) throw GraphError(decl.name + ": a compute pass needs a .comp shader");
  desc.bindings = declared_layout(decl, desc_of);
  desc.push_constant_bytes = decl.push_constant_bytes;
  return desc;
}

}  // namespace nightcap
