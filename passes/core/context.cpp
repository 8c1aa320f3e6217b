// PassContext: what a pass may reach while it records, checked against its declaration.
#include "passes/core/context.h"

#include "passes/core/declared_pipeline.h"
#include "passes/core/execution_state.h"
#include "passes/core/resource_commands.h"

#include <algorithm>

namespace nightcap {
namespace {

// Each distinct pipeline or sampler state once, in the order the pass first used it.
void record_state(nlohmann::json& list, nlohmann::json state) {
  if (std::find(list.begin(), list.end(), state) == list.end()) list.push_back(std::move(state));
}

}  // namespace

PassContext::PassContext(Shared& shared, const CompiledPass& pass) : shared_(shared), pass_(pass) {}

double PassContext::param_value(const std::string& name, std::initializer_list<ParamType> types) const {
  const ParamDecl* param = pass_.decl->find_param(name);
  if (!param) throw GraphError(pass() + ": reads undeclared parameter '" + name + "'");
  if (std::find(types.begin(), types.end(), param->type) == types.end())
    throw GraphError(pass() + ": reads " + type_name(param->type) + " parameter '" + name + "' as " +
                     type_name(*types.begin()));
  return pass_.params.at(name);
}

double PassContext::param_float(const std::string& name) const { return param_value(name, {ParamType::real}); }

int64_t PassContext::param_int(const std::string& name) const {
  return int64_t(param_value(name, {ParamType::integer, ParamType::choice}));
}

bool PassContext::flag(const std::string& name) const { return param_value(name, {ParamType::boolean}) != 0; }

const BoundUse* PassContext::find_use(const std::string& resource) const {
  for (const BoundUse& u : pass_.outputs)
    if (u.resource == resource) return &u;
  for (const BoundUse& u : pass_.inputs)
    if (u.resource == resource) return &u;
  return nullptr;
}

VkBuffer PassContext::indirect_args(const std::string& resource, uint64_t offset, uint64_t bytes) const {
  const bool declared = std::any_of(pass_.inputs.begin(), pass_.inputs.end(), [&](const BoundUse& u) {
    return u.resource == resource && u.use == Use::indirect_args;
  });
  // Arguments the pass computed itself reach the indirect read through its storage_barrier().
  const bool own = std::any_of(pass_.outputs.begin(), pass_.outputs.end(), [&](const BoundUse& u) {
    return u.resource == resource && u.use == Use::storage_write && u.desc.is_buffer;
  });
  if (!declared && !own)
    throw GraphError(pass() + ": takes indirect arguments from '" + resource +
                     "' without declaring it as Use::indirect_args or writing it as a storage buffer");
  const uint64_t size = desc(resource).buffer_size;
  if (offset > size || bytes > size - offset)
    throw GraphError(pass() + ": indirect arguments at bytes " + std::to_string(offset) + "+" + std::to_string(bytes) +
                     " of '" + resource + "', which holds " + std::to_string(size));
  return buffer(resource);
}

void PassContext::dispatch_indirect(const std::string& resource, uint64_t offset) {
  vkCmdDispatchIndirect(cmd(), indirect_args(resource, offset, sizeof(VkDispatchIndirectCommand)), offset);
}

void PassContext::draw_indexed_indirect(const std::string& resource, uint64_t offset, uint32_t count, uint32_t stride) {
  if (count == 0) return;
  const uint64_t bytes = uint64_t(count - 1) * stride + sizeof(VkDrawIndexedIndirectCommand);
  vkCmdDrawIndexedIndirect(cmd(), indirect_args(resource, offset, bytes), offset, count, stride);
}

const ResourceDesc& PassContext::desc(const std::string& resource) const {
  if (!find_use(resource)) throw GraphError(pass() + ": uses undeclared resource '" + resource + "'");
  return shared_.resources.count(resource) ? shared_.resources.at(resource).desc : find_use(resource)->desc;
}

std::span<const uint8_t> PassContext::host(const std::string& resource) const {
  if (!find_use(resource)) throw GraphError(pass() + ": uses undeclared resource '" + resource + "'");
  auto it = shared_.host.find(resource);
  if (it == shared_.host.end() || !it->second)
    throw GraphError(pass() + ": '" + resource + "' is not known on the host");
  return *it->second;
}

bool PassContext::reads(const std::string& resource) const {
  return std::any_of(pass_.inputs.begin(), pass_.inputs.end(),
                     [&](const BoundUse& u) { return u.resource == resource; });
}

std::vector<std::string> PassContext::inputs_with_prefix(const std::string& prefix) const {
  std::vector<std::string> names;
  for (const BoundUse& u : pass_.inputs)
    if (u.resource.rfind(prefix, 0) == 0) names.push_back(u.resource);
  return names;
}

std::vector<uint8_t>& PassContext::output(const std::string& resource) {
  bool declared = false;
  for (const BoundUse& u : pass_.outputs) declared |= u.resource == resource;
  if (!declared) throw GraphError(pass() + ": writes undeclared output '" + resource + "'");
  return shared_.cpu_outputs[resource];
}

VkCommandBuffer PassContext::cmd() const { return shared_.cmd; }
GpuDevice& PassContext::gpu() const { return shared_.gpu; }

VkBuffer PassContext::buffer(const std::string& resource) const {
  if (!find_use(resource)) throw GraphError(pass() + ": uses undeclared resource '" + resource + "'");
  return shared_.resources.at(resource).buffer.buffer;
}

VkImageView PassContext::view(const std::string& resource, ViewAspect aspect, int mip, int layer) {
  if (!find_use(resource)) throw GraphError(pass() + ": uses undeclared resource '" + resource + "'");
  PhysicalResource& r = shared_.resources.at(resource);
  const ImageExtent& e = r.desc.extent;
  if (mip >= int(e.mips) || layer >= int(e.layers))
    throw GraphError(pass() + ": asks for mip " + std::to_string(mip) + " layer " + std::to_string(layer) + " of '" +
                     resource + "', which has " + std::to_string(e.mips) + " mips and " + std::to_string(e.layers) +
                     " layers");
  auto key = std::make_tuple(static_cast<int>(aspect), mip, layer);
  auto it = r.views.find(key);
  if (it != r.views.end()) return it->second;
  auto info = vk_struct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  info.image = r.image.image;
  if (e.depth > 1)
    info.viewType = VK_IMAGE_VIEW_TYPE_3D;
  else if (layer >= 0 || e.layers == 1)
    info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  else if (r.desc.cube)
    info.viewType = e.layers == 6 ? VK_IMAGE_VIEW_TYPE_CUBE : VK_IMAGE_VIEW_TYPE_CUBE_ARRAY;
  else
    info.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
  info.format = r.desc.format;
  VkImageAspectFlags aspects = natural_aspects(r.desc.format);
  if (aspect == ViewAspect::depth) aspects = VK_IMAGE_ASPECT_DEPTH_BIT;
  if (aspect == ViewAspect::stencil) aspects = VK_IMAGE_ASPECT_STENCIL_BIT;
  info.subresourceRange = {aspects, mip < 0 ? 0u : uint32_t(mip), mip < 0 ? e.mips : 1u,
                           layer < 0 ? 0u : uint32_t(layer), layer < 0 ? e.layers : 1u};
  VkImageView view = gpu().create_view(info, resource, e.mips, e.layers);
  r.views[key] = view;
  return view;
}

void PassContext::check_declared(const std::string& resource, int mip, int layer, VkImageLayout layout) const {
  const ResourceDesc& d = desc(resource);
  auto declared = [&](uint32_t m, uint32_t l) {
    for (const auto* uses : {&pass_.inputs, &pass_.outputs})
      for (const BoundUse& u : *uses)
        if (u.resource == resource && u.range.contains(m, l) &&
            required_state(u.use, pass_.decl->type, is_depth(d)).layout == layout)
          return true;
    return false;
  };
  for (uint32_t m = mip < 0 ? 0 : mip; m < (mip < 0 ? d.extent.mips : uint32_t(mip) + 1); ++m)
    for (uint32_t l = layer < 0 ? 0 : layer; l < (layer < 0 ? d.extent.layers : uint32_t(layer) + 1); ++l)
      if (!declared(m, l))
        throw GraphError(pass() + ": uses mip " + std::to_string(m) + " layer " + std::to_string(l) + " of '" +
                         resource + "' in a way it did not declare (the graph's barriers would not cover it)");
}

void PassContext::bind_pipeline(const std::vector<int32_t>& specialization) {
  const DescOf desc_of = declared_descs();
  if (declaration().type == PassType::compute) {
    ComputePipelineDesc desc = declared_compute_pipeline(declaration(), desc_of);
    desc.specialization = specialization;
    bind(desc);
  } else {
    GraphicsPipelineDesc desc = declared_graphics_pipeline(declaration(), desc_of);
    desc.specialization = specialization;
    bind(desc);
  }
}

uint32_t PassContext::slot(const std::string& resource) const {
  for (const DeclaredSlot& s : declared_slots(declaration(), declared_descs()))
    if (s.use->bound_name() == resource) return s.first;
  throw GraphError(pass() + ": declares no binding for '" + resource + "'");
}

DescOf PassContext::declared_descs() const {
  return [this](const std::string& resource) -> const ResourceDesc& { return desc(resource); };
}

std::string PassContext::binding_preamble() const { return binding_defines(declaration(), declared_descs()); }

void PassContext::bind(const GraphicsPipelineDesc& desc) {
  const std::string bindings = binding_preamble();
  auto code = [&](const std::string& path) {
    auto spirv = shared_.shaders(pass(), path, bindings);
    shared_.current->spirv[path] = spirv;
    return spirv;
  };
  const auto& entry = shared_.cache.graphics(desc, code(desc.vertex),
                                             desc.fragment.empty() ? std::vector<uint32_t>{} : code(desc.fragment));
  vkCmdBindPipeline(cmd(), VK_PIPELINE_BIND_POINT_GRAPHICS, entry.pipeline);
  record_state(shared_.current->pipelines, describe(desc));
  if (desc.raster.per_draw_faces) {
    vkCmdSetCullMode(cmd(), desc.raster.cull_mode);
    vkCmdSetFrontFace(cmd(), desc.raster.front_face);
  }
  layout_ = entry.layout;
  bind_point_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  push_constant_bytes_ = desc.push_constant_bytes;
}

void PassContext::bind(const ComputePipelineDesc& desc) {
  auto spirv = shared_.shaders(pass(), desc.shader, binding_preamble());
  shared_.current->spirv[desc.shader] = spirv;
  const auto& entry = shared_.cache.compute(desc, spirv);
  vkCmdBindPipeline(cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, entry.pipeline);
  record_state(shared_.current->pipelines, describe(desc));
  layout_ = entry.layout;
  bind_point_ = VK_PIPELINE_BIND_POINT_COMPUTE;
  push_constant_bytes_ = desc.push_constant_bytes;
}

void PassContext::push(const std::vector<Binding>& bindings) {
  if (bindings.empty()) return;  // a shader without resources (Vulkan wants at least one write)
  std::vector<VkWriteDescriptorSet> writes;
  std::vector<VkDescriptorBufferInfo> buffers;
  std::vector<VkDescriptorImageInfo> images;
  buffers.reserve(bindings.size());
  images.reserve(bindings.size());
  for (const Binding& b : bindings) {
    auto w = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstBinding = b.binding;
    w.descriptorCount = 1;
    w.descriptorType = b.type;
    if (b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || b.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER) {
      buffers.push_back({buffer(b.resource), b.offset, b.range});
      w.pBufferInfo = &buffers.back();
    } else {
      const bool storage = b.type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      const ResourceDesc& d = desc(b.resource);
      VkImageLayout layout = storage       ? VK_IMAGE_LAYOUT_GENERAL
                             : is_depth(d) ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
                                           : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
      ViewAspect aspect = b.aspect;
      if (aspect == ViewAspect::natural && is_depth(d)) aspect = ViewAspect::depth;
      check_declared(b.resource, b.mip, b.layer, layout);
      images.push_back({b.sampler, view(b.resource, aspect, b.mip, b.layer), layout});
      w.pImageInfo = &images.back();
    }
    writes.push_back(w);
  }
  gpu().push_descriptors(cmd(), bind_point_, layout_, writes);
}

void PassContext::push_declared(std::optional<uint32_t> level) {
  push(declared_bindings(
      declaration(), declared_descs(), [this](const SamplerDesc& d) { return sampler(d); }, level));
}

void PassContext::push_draw_textures(std::span<const DrawTexture> textures) {
  const DeclaredSlot slot = prefix_slot(declaration(), declared_descs());
  if (textures.size() != slot.count)
    throw GraphError(pass() + ": " + std::to_string(textures.size()) + " textures for the " +
                     std::to_string(slot.count) + " slots of '" + slot.use->resource + "'");
  std::vector<Binding> bindings;
  for (uint32_t i = 0; i < slot.count; ++i) {
    if (textures[i].resource.rfind(slot.use->resource, 0) != 0)
      throw GraphError(pass() + ": '" + textures[i].resource + "' is not one of its '" + slot.use->resource +
                       "' reads");
    bindings.push_back(Binding::texture(slot.first + i, textures[i].resource, sampler(textures[i].sampler)));
  }
  push(bindings);
}

void PassContext::push_constants(const void* data, uint32_t bytes) {
  if (bytes > push_constant_bytes_) throw GraphError(pass() + ": push constants larger than the pipeline declares");
  vkCmdPushConstants(cmd(), layout_, VK_SHADER_STAGE_ALL, 0, bytes, data);
}

VkSampler PassContext::sampler(const SamplerDesc& desc) {
  record_state(shared_.current->samplers, describe(desc));
  return shared_.cache.sampler(desc);
}

VkSampler PassContext::nearest_clamp() { return sampler(nearest_clamp_sampler()); }

void PassContext::begin_rendering(const std::vector<std::string>& colors, const std::string& depth, uint32_t mip,
                                  uint32_t layer) {
  auto attachment = [&](const std::string& name, ViewAspect aspect, VkImageLayout layout) {
    const BoundUse* use = find_use(name);
    if (!use) throw GraphError(pass() + ": renders to undeclared '" + name + "'");
    check_declared(name, int(mip), int(layer), layout);
    auto a = vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    a.imageView = view(name, aspect, int(mip), int(layer));
    a.imageLayout = layout;
    a.loadOp = use->modifies || (mip == 0 && copied_layers_.count({name, layer})) ? VK_ATTACHMENT_LOAD_OP_LOAD
                                                                                  : VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.clearValue = desc(name).clear;
    return a;
  };
  std::vector<VkRenderingAttachmentInfo> color_attachments;
  for (const std::string& c : colors)
    color_attachments.push_back(attachment(c, ViewAspect::natural, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL));
  const std::string& first = colors.empty() ? depth : colors.front();
  const ImageExtent base = desc(first).extent;
  const VkExtent2D extent{mip_size(base.width, mip), mip_size(base.height, mip)};
  auto info = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
  info.renderArea = {{0, 0}, extent};
  info.layerCount = 1;
  info.colorAttachmentCount = static_cast<uint32_t>(color_attachments.size());
  info.pColorAttachments = color_attachments.data();
  VkRenderingAttachmentInfo depth_attachment{};
  if (!depth.empty()) {
    depth_attachment = attachment(depth, ViewAspect::natural, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    info.pDepthAttachment = &depth_attachment;
    if (format_info(desc(depth).format)->has_stencil) info.pStencilAttachment = &depth_attachment;
  }
  vkCmdBeginRendering(cmd(), &info);
  VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0, 1};
  VkRect2D scissor{{0, 0}, {extent.width, extent.height}};
  vkCmdSetViewport(cmd(), 0, 1, &viewport);
  vkCmdSetScissor(cmd(), 0, 1, &scissor);
  vkCmdSetStencilReference(cmd(), VK_STENCIL_FACE_FRONT_AND_BACK, 0);
}

void PassContext::copy_layer(const std::string& from, uint32_t from_layer, const std::string& to, uint32_t to_layer,
                             int32_t dx, int32_t dy) {
  const BoundUse* source = nullptr;
  const BoundUse* target = nullptr;
  for (const BoundUse& u : pass_.inputs)
    if (u.resource == from && !u.desc.is_buffer && u.range.contains(0, from_layer)) source = &u;
  for (const BoundUse& u : pass_.outputs)
    if (u.resource == to && !u.desc.is_buffer && u.range.contains(0, to_layer)) target = &u;
  if (!source || !target || from == to)
    throw GraphError(pass() + ": copies layer " + std::to_string(from_layer) + " of '" + from + "' into layer " +
                     std::to_string(to_layer) + " of '" + to + "' without reading the one and writing the other there");
  const PhysicalResource& src = shared_.resources.at(from);
  const PhysicalResource& dst = shared_.resources.at(to);
  const ImageExtent &a = src.desc.extent, &b = dst.desc.extent;
  if (src.desc.format != dst.desc.format || a.width != b.width || a.height != b.height || a.depth != 1)
    throw GraphError(pass() + ": copies '" + from + "' into '" + to + "', which differ in format or size");
  const bool depth = is_depth(dst.desc);
  const AccessState read = required_state(source->use, pass_.decl->type, depth);
  const AccessState written = required_state(target->use, pass_.decl->type, depth);
  const AccessState copy_from = transfer_state(false), copy_to = transfer_state(true);
  const Subresources source_layer{0, 1, from_layer, 1}, target_layer{0, 1, to_layer, 1};
  issue(cmd(), shared_.resources, {{from, source_layer, {read, copy_from}}, {to, target_layer, {written, copy_to}}},
        {});
  // The part of `to` whose texels have a source.
  const int32_t w = int32_t(b.width), h = int32_t(b.height);
  const int32_t x0 = std::max(0, -dx), y0 = std::max(0, -dy), x1 = std::min(w, w - dx), y1 = std::min(h, h - dy);
  if (dx != 0 || dy != 0) {
    clear_to(cmd(), dst, target_layer, dst.desc.clear);
    issue(cmd(), shared_.resources, {{to, target_layer, {copy_to, copy_to}}}, {});
  }
  if (x0 < x1 && y0 < y1) {
    const VkImageAspectFlags aspects = natural_aspects(dst.desc.format);
    std::vector<VkImageCopy> regions;
    for (VkImageAspectFlags aspect :
         {VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_ASPECT_STENCIL_BIT}) {
      if (!(aspects & aspect)) continue;
      VkImageCopy region{};
      region.srcSubresource = {aspect, 0, from_layer, 1};
      region.dstSubresource = {aspect, 0, to_layer, 1};
      region.srcOffset = {x0 + dx, y0 + dy, 0};
      region.dstOffset = {x0, y0, 0};
      region.extent = {uint32_t(x1 - x0), uint32_t(y1 - y0), 1};
      regions.push_back(region);
    }
    vkCmdCopyImage(cmd(), src.image.image, copy_from.layout, dst.image.image, copy_to.layout, uint32_t(regions.size()),
                   regions.data());
  }
  issue(cmd(), shared_.resources, {{from, source_layer, {copy_from, read}}, {to, target_layer, {copy_to, written}}},
        {});
  copied_layers_.insert({to, to_layer});
}

void PassContext::copy_resource(const std::string& from, const std::string& to) {
  auto whole = [](const BoundUse& u) {
    const ImageExtent& e = u.desc.extent;
    return u.desc.is_buffer || (u.range.contains(0, 0) && u.range.contains(e.mips - 1, e.layers - 1));
  };
  const BoundUse* source = nullptr;
  const BoundUse* target = nullptr;
  for (const BoundUse& u : pass_.inputs)
    if (u.resource == from && whole(u)) source = &u;
  for (const BoundUse& u : pass_.outputs)
    if (u.resource == to && whole(u)) target = &u;
  if (!source || !target || from == to)
    throw GraphError(pass() + ": copies '" + from + "' into '" + to +
                     "' without reading the whole of the one and writing the whole of the other");
  const PhysicalResource& src = shared_.resources.at(from);
  const PhysicalResource& dst = shared_.resources.at(to);
  if (src.desc.is_buffer != dst.desc.is_buffer || src.desc.format != dst.desc.format ||
      src.desc.extent != dst.desc.extent || src.desc.buffer_size != dst.desc.buffer_size)
    throw GraphError(pass() + ": copies '" + from + "' into '" + to + "', which differ in format or size");
  const bool depth = is_depth(dst.desc);
  const AccessState read = required_state(source->use, pass_.decl->type, depth);
  const AccessState written = required_state(target->use, pass_.decl->type, depth);
  const AccessState copy_from = transfer_state(false), copy_to = transfer_state(true);
  const Subresources all{};
  issue(cmd(), shared_.resources, {{from, all, {read, copy_from}}, {to, all, {written, copy_to}}}, {});
  copy_whole(cmd(), src, dst);
  issue(cmd(), shared_.resources, {{from, all, {copy_from, read}}, {to, all, {copy_to, written}}}, {});
}

void PassContext::clear_layers(const std::string& to, uint32_t first_layer, uint32_t count, const VkClearValue& value) {
  if (count == 0) return;
  const BoundUse* target = nullptr;
  for (const BoundUse& u : pass_.outputs)
    if (u.resource == to && !u.desc.is_buffer && u.range.contains(0, first_layer) &&
        u.range.contains(u.desc.extent.mips - 1, first_layer + count - 1))
      target = &u;
  if (!target)
    throw GraphError(pass() + ": clears layers " + std::to_string(first_layer) + "+" + std::to_string(count) + " of '" +
                     to + "' without writing them");
  const PhysicalResource& dst = shared_.resources.at(to);
  const AccessState written = required_state(target->use, pass_.decl->type, is_depth(dst.desc));
  const AccessState clearing = transfer_state(true);
  const Subresources layers{0, dst.desc.extent.mips, first_layer, count};
  issue(cmd(), shared_.resources, {{to, layers, {written, clearing}}}, {});
  clear_to(cmd(), dst, layers, value);
  issue(cmd(), shared_.resources, {{to, layers, {clearing, written}}}, {});
}

void PassContext::begin_rendering() { begin_rendering(colour_targets(declaration()), depth_target(declaration())); }

void PassContext::end_rendering() { vkCmdEndRendering(cmd()); }

void PassContext::storage_barrier() {
  auto barrier = vk_struct<VkMemoryBarrier2>(VK_STRUCTURE_TYPE_MEMORY_BARRIER_2);
  // The indirect stage on both sides: a dispatch after an indirect one may write the buffer its
  // arguments came from (a storage binding that is not readonly counts as written).
  barrier.srcStageMask = barrier.dstStageMask =
      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
  barrier.srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                          VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
  auto dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd(), &dep);
}

}  // namespace nightcap
