#include "passes/core/executor.h"

#include <chrono>
#include <cstring>

namespace nightcap {

struct PhysicalResource {
  ResourceDesc desc;
  GpuImage image;
  GpuBuffer buffer;
  SyncState sync;
  std::map<std::pair<int, int>, VkImageView> views;  // (aspect, mip) -> view
  int version = -1;                                  // current version index
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

namespace {

bool is_depth(const ResourceDesc& d) { return !d.is_buffer && format_info(d.format)->is_depth; }

VkImageAspectFlags natural_aspects(VkFormat format) {
  const FormatInfo f = *format_info(format);
  if (f.has_stencil) return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
  return f.is_depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

VkImageAspectFlags raw_aspect(VkFormat format, uint32_t aspect) {
  const FormatInfo f = *format_info(format);
  if (!f.is_depth) return VK_IMAGE_ASPECT_COLOR_BIT;
  return aspect == 1 ? VK_IMAGE_ASPECT_STENCIL_BIT : VK_IMAGE_ASPECT_DEPTH_BIT;
}

VkImageUsageFlags usage_for(Use use) {
  switch (use) {
    case Use::sampled:
      return VK_IMAGE_USAGE_SAMPLED_BIT;
    case Use::storage_read:
    case Use::storage_write:
      return VK_IMAGE_USAGE_STORAGE_BIT;
    case Use::color_attachment:
      return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    case Use::depth_attachment:
      return VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    default:
      return 0;
  }
}

void transition(VkCommandBuffer cmd, PhysicalResource& r, AccessState next, bool discard = false) {
  if (r.desc.is_buffer) next.layout = VK_IMAGE_LAYOUT_UNDEFINED;
  auto plan = plan_barrier(r.sync, next, discard);
  if (!plan) return;
  auto dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  auto image = vk_struct<VkImageMemoryBarrier2>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2);
  auto buffer = vk_struct<VkBufferMemoryBarrier2>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2);
  const VkPipelineStageFlags2 src_stages =
      plan->before.stages ? plan->before.stages : VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT;
  if (r.desc.is_buffer) {
    buffer.srcStageMask = src_stages;
    buffer.srcAccessMask = plan->before.access;
    buffer.dstStageMask = plan->after.stages;
    buffer.dstAccessMask = plan->after.access;
    buffer.srcQueueFamilyIndex = buffer.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    buffer.buffer = r.buffer.buffer;
    buffer.size = VK_WHOLE_SIZE;
    dep.bufferMemoryBarrierCount = 1;
    dep.pBufferMemoryBarriers = &buffer;
  } else {
    image.srcStageMask = src_stages;
    image.srcAccessMask = plan->before.access;
    image.dstStageMask = plan->after.stages;
    image.dstAccessMask = plan->after.access;
    image.oldLayout = plan->before.layout;
    image.newLayout = plan->after.layout;
    image.srcQueueFamilyIndex = image.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    image.image = r.image.image;
    image.subresourceRange = {natural_aspects(r.desc.format), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &image;
  }
  vkCmdPipelineBarrier2(cmd, &dep);
}

std::vector<VkBufferImageCopy> raw_copy_regions(const ResourceDesc& d) {
  const FormatInfo f = *format_info(d.format);
  std::vector<VkBufferImageCopy> regions;
  for (uint32_t a = 0; a < aspect_count(f); ++a)
    for (uint32_t m = 0; m < d.extent.mips; ++m) {
      VkBufferImageCopy region{};
      region.bufferOffset = raw_subresource_offset(f, d.extent, a, m, 0);
      region.imageSubresource = {raw_aspect(d.format, a), m, 0, d.extent.layers};
      region.imageExtent = {mip_size(d.extent.width, m), mip_size(d.extent.height, m), mip_size(d.extent.depth, m)};
      regions.push_back(region);
    }
  return regions;
}

void allocate(GpuDevice& gpu, PhysicalResource& r, VkImageUsageFlags usage) {
  const ResourceDesc& d = r.desc;
  if (d.is_buffer) {
    r.buffer = gpu.create_buffer(std::max<uint64_t>(d.buffer_size, 16),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                     VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 false);
    return;
  }
  auto info = vk_struct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = d.extent.depth > 1 ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  info.format = d.format;
  info.extent = {d.extent.width, d.extent.height, d.extent.depth};
  info.mipLevels = d.extent.mips;
  info.arrayLayers = d.extent.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  // Sampling depth uses DEPTH_STENCIL_READ_ONLY_OPTIMAL, which needs attachment usage.
  if (format_info(d.format)->is_depth) info.usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  r.image = gpu.create_image(info);
}

struct Staging {
  GpuBuffer buffer;
  int version;
};

}  // namespace

const VersionData* Execution::final_version(const std::string& resource) const {
  for (auto it = versions.rbegin(); it != versions.rend(); ++it)
    if (it->resource == resource) return &*it;
  return nullptr;
}

// ---- PassContext ---------------------------------------------------------------------------

PassContext::PassContext(Shared& shared, const CompiledPass& pass, const ParamValues& params)
    : shared_(shared), pass_(pass), params_(params) {}

double PassContext::param(const std::string& name) const {
  auto it = params_.find(name);
  if (it == params_.end()) throw GraphError(pass() + ": reads undeclared parameter '" + name + "'");
  return it->second;
}

const BoundUse* PassContext::find_use(const std::string& resource) const {
  for (const BoundUse& u : pass_.outputs)
    if (u.resource == resource) return &u;
  for (const BoundUse& u : pass_.inputs)
    if (u.resource == resource) return &u;
  return nullptr;
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

VkImageView PassContext::view(const std::string& resource, ViewAspect aspect, int mip) {
  if (!find_use(resource)) throw GraphError(pass() + ": uses undeclared resource '" + resource + "'");
  PhysicalResource& r = shared_.resources.at(resource);
  auto key = std::make_pair(static_cast<int>(aspect), mip);
  auto it = r.views.find(key);
  if (it != r.views.end()) return it->second;
  auto info = vk_struct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  info.image = r.image.image;
  info.viewType = r.desc.extent.depth > 1    ? VK_IMAGE_VIEW_TYPE_3D
                  : r.desc.extent.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                                             : VK_IMAGE_VIEW_TYPE_2D;
  info.format = r.desc.format;
  VkImageAspectFlags aspects = natural_aspects(r.desc.format);
  if (aspect == ViewAspect::depth) aspects = VK_IMAGE_ASPECT_DEPTH_BIT;
  if (aspect == ViewAspect::stencil) aspects = VK_IMAGE_ASPECT_STENCIL_BIT;
  info.subresourceRange = {aspects, mip < 0 ? 0u : static_cast<uint32_t>(mip), mip < 0 ? r.desc.extent.mips : 1u, 0,
                           r.desc.extent.layers};
  VkImageView view;
  vk_check(vkCreateImageView(gpu().device(), &info, nullptr, &view), "vkCreateImageView");
  r.views[key] = view;
  return view;
}

void PassContext::bind(const GraphicsPipelineDesc& desc) {
  auto code = [&](const std::string& path) {
    auto spirv = shared_.shaders(pass(), path);
    shared_.current->spirv[path] = spirv;
    return spirv;
  };
  const auto& entry = shared_.cache.graphics(desc, code(desc.vertex),
                                             desc.fragment.empty() ? std::vector<uint32_t>{} : code(desc.fragment));
  vkCmdBindPipeline(cmd(), VK_PIPELINE_BIND_POINT_GRAPHICS, entry.pipeline);
  layout_ = entry.layout;
  bind_point_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  push_constant_bytes_ = desc.push_constant_bytes;
}

void PassContext::bind(const ComputePipelineDesc& desc) {
  auto spirv = shared_.shaders(pass(), desc.shader);
  shared_.current->spirv[desc.shader] = spirv;
  const auto& entry = shared_.cache.compute(desc, spirv);
  vkCmdBindPipeline(cmd(), VK_PIPELINE_BIND_POINT_COMPUTE, entry.pipeline);
  layout_ = entry.layout;
  bind_point_ = VK_PIPELINE_BIND_POINT_COMPUTE;
  push_constant_bytes_ = desc.push_constant_bytes;
}

void PassContext::push(const std::vector<Binding>& bindings) {
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
      images.push_back({b.sampler, view(b.resource, aspect, b.mip), layout});
      w.pImageInfo = &images.back();
    }
    writes.push_back(w);
  }
  gpu().push_descriptors(cmd(), bind_point_, layout_, writes);
}

void PassContext::push_constants(const void* data, uint32_t bytes) {
  if (bytes > push_constant_bytes_) throw GraphError(pass() + ": push constants larger than the pipeline declares");
  vkCmdPushConstants(cmd(), layout_, VK_SHADER_STAGE_ALL, 0, bytes, data);
}

VkSampler PassContext::sampler(const SamplerDesc& desc) { return shared_.cache.sampler(desc); }

VkSampler PassContext::nearest_clamp() {
  SamplerDesc d;
  d.mag_filter = d.min_filter = VK_FILTER_NEAREST;
  d.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  d.wrap_u = d.wrap_v = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  return sampler(d);
}

void PassContext::begin_rendering(const std::vector<std::string>& colors, const std::string& depth) {
  auto attachment = [&](const std::string& name, ViewAspect aspect, VkImageLayout layout) {
    const BoundUse* use = find_use(name);
    if (!use) throw GraphError(pass() + ": renders to undeclared '" + name + "'");
    auto a = vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    a.imageView = view(name, aspect, 0);
    a.imageLayout = layout;
    a.loadOp = use->modifies ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.clearValue = desc(name).clear;
    return a;
  };
  std::vector<VkRenderingAttachmentInfo> color_attachments;
  for (const std::string& c : colors)
    color_attachments.push_back(attachment(c, ViewAspect::natural, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL));
  const std::string& first = colors.empty() ? depth : colors.front();
  const ImageExtent extent = desc(first).extent;
  auto info = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
  info.renderArea = {{0, 0}, {extent.width, extent.height}};
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
  vkCmdSetCullMode(cmd(), VK_CULL_MODE_NONE);
  vkCmdSetFrontFace(cmd(), VK_FRONT_FACE_COUNTER_CLOCKWISE);
  vkCmdSetStencilReference(cmd(), VK_STENCIL_FACE_FRONT_AND_BACK, 0);
}

void PassContext::end_rendering() { vkCmdEndRendering(cmd()); }

void PassContext::storage_barrier() {
  auto barrier = vk_struct<VkMemoryBarrier2>(VK_STRUCTURE_TYPE_MEMORY_BARRIER_2);
  barrier.srcStageMask = barrier.dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  barrier.srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
  auto dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd(), &dep);
}

// ---- execution -----------------------------------------------------------------------------

Execution execute_graph(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph,
                        const std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>& imports,
                        const ExecutionOptions& options) {
  Execution result;
  result.passes.resize(graph.passes.size());
  PassContext::Shared shared{gpu, cache, options.shaders, VK_NULL_HANDLE, {}, {}, {}, nullptr};
  std::map<std::string, int> latest;  // resource -> current version index
  auto add_version = [&](const std::string& name, const ResourceDesc& desc,
                         std::shared_ptr<const std::vector<uint8_t>> bytes) {
    result.versions.push_back({name, desc, std::move(bytes)});
    latest[name] = static_cast<int>(result.versions.size()) - 1;
    return latest[name];
  };
  for (const auto& [name, bytes] : imports) {
    auto it = graph.resources.find(name);
    if (it == graph.resources.end()) continue;
    if (bytes->size() != it->second.raw_bytes())
      throw GraphError("imported '" + name + "' has " + std::to_string(bytes->size()) + " bytes, expected " +
                       std::to_string(it->second.raw_bytes()));
    shared.host[name] = bytes;
    add_version(name, it->second, bytes);
  }
  auto params_of = [&](const PassDecl& decl) {
    ParamValues values = decl.default_params();
    auto it = options.params.find(decl.name);
    if (it != options.params.end())
      for (const auto& [k, v] : it->second) values[k] = v;
    return values;
  };

  // CPU passes: they may read only host data, so they all run before the GPU work.
  for (size_t i = 0; i < graph.passes.size(); ++i) {
    CompiledPass& pass = graph.passes[i];
    if (pass.culled || pass.decl->type != PassType::cpu) continue;
    PassExecution& exec = result.passes[i];
    for (const BoundUse& in : pass.inputs) {
      if (!shared.host.count(in.resource))
        throw GraphError(pass.decl->name + ": a CPU pass cannot read GPU-produced '" + in.resource + "'");
      exec.inputs.push_back(latest.at(in.resource));
    }
    shared.cpu_outputs.clear();
    if (pass.runs) {
      const ParamValues params = params_of(*pass.decl);
      PassContext ctx(shared, pass, params);
      auto start = std::chrono::steady_clock::now();
      pass.decl->execute(ctx);
      exec.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    for (BoundUse& out : pass.outputs) {
      auto bytes = std::make_shared<std::vector<uint8_t>>(std::move(shared.cpu_outputs[out.resource]));
      if (out.desc.is_buffer) {
        out.desc.buffer_size = bytes->size();
      } else if (!pass.runs) {
        bytes->assign(out.desc.raw_bytes(), 0);  // a skipped CPU pass leaves cleared images
      } else if (bytes->size() != out.desc.raw_bytes()) {
        throw GraphError(pass.decl->name + ": wrote " + std::to_string(bytes->size()) + " bytes to '" + out.resource +
                         "', which holds " + std::to_string(out.desc.raw_bytes()));
      }
      graph.resources[out.resource] = out.desc;
      shared.host[out.resource] = bytes;
      exec.outputs.push_back(add_version(out.resource, out.desc, bytes));
    }
  }
  // Later passes saw the declared (size 0) descriptors of CPU buffers: refresh them.
  for (CompiledPass& pass : graph.passes)
    for (BoundUse& in : pass.inputs)
      if (graph.resources.count(in.resource)) in.desc = graph.resources.at(in.resource);

  // Allocate what the GPU passes touch.
  std::map<std::string, VkImageUsageFlags> usage;
  for (const CompiledPass& pass : graph.passes) {
    if (pass.culled || pass.decl->type == PassType::cpu) continue;
    for (const BoundUse& u : pass.inputs) usage[u.resource] |= usage_for(u.use);
    for (const BoundUse& u : pass.outputs) usage[u.resource] |= usage_for(u.use);
  }
  struct Cleanup {
    GpuDevice& gpu;
    PassContext::Shared& shared;
    std::vector<Staging> staging;
    VkQueryPool queries = VK_NULL_HANDLE;
    ~Cleanup() {
      for (auto& [name, r] : shared.resources) {
        for (auto& [key, view] : r.views) vkDestroyImageView(gpu.device(), view, nullptr);
        gpu.destroy(r.image);
        gpu.destroy(r.buffer);
      }
      for (Staging& s : staging) gpu.destroy(s.buffer);
      if (queries) vkDestroyQueryPool(gpu.device(), queries, nullptr);
    }
  } cleanup{gpu, shared, {}, VK_NULL_HANDLE};
  for (const auto& [name, flags] : usage) {
    PhysicalResource& r = shared.resources[name];
    r.desc = graph.resources.at(name);
    allocate(gpu, r, flags);
  }

  auto query_info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  query_info.queryCount = static_cast<uint32_t>(2 * graph.passes.size() + 2);
  vk_check(vkCreateQueryPool(gpu.device(), &query_info, nullptr, &cleanup.queries), "vkCreateQueryPool");
  vkResetQueryPool(gpu.device(), cleanup.queries, 0, query_info.queryCount);

  VkCommandBuffer cmd = gpu.begin_commands();
  shared.cmd = cmd;
  try {
    // Uploads of host data the GPU reads.
    for (auto& [name, r] : shared.resources) {
      auto host = shared.host.find(name);
      if (host == shared.host.end()) continue;
      const std::vector<uint8_t>& bytes = *host->second;
      GpuBuffer staging = gpu.create_buffer(std::max<size_t>(bytes.size(), 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
      if (!bytes.empty()) std::memcpy(staging.mapped, bytes.data(), bytes.size());
      cleanup.staging.push_back({staging, -1});
      transition(cmd, r, transfer_state(true), true);
      if (r.desc.is_buffer) {
        if (!bytes.empty()) {
          VkBufferCopy copy{0, 0, bytes.size()};
          vkCmdCopyBuffer(cmd, staging.buffer, r.buffer.buffer, 1, &copy);
        }
      } else {
        auto regions = raw_copy_regions(r.desc);
        vkCmdCopyBufferToImage(cmd, staging.buffer, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                               static_cast<uint32_t>(regions.size()), regions.data());
      }
    }
    auto read_back = [&](PhysicalResource& r, int version) {
      GpuBuffer staging =
          gpu.create_buffer(std::max<uint64_t>(r.desc.raw_bytes(), 16), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
      cleanup.staging.push_back({staging, version});
      transition(cmd, r, transfer_state(false));
      if (r.desc.is_buffer) {
        if (r.desc.buffer_size) {
          VkBufferCopy copy{0, 0, r.desc.buffer_size};
          vkCmdCopyBuffer(cmd, r.buffer.buffer, staging.buffer, 1, &copy);
        }
      } else {
        auto regions = raw_copy_regions(r.desc);
        vkCmdCopyImageToBuffer(cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer,
                               static_cast<uint32_t>(regions.size()), regions.data());
      }
    };
    auto last_writer_of = [&](const std::string& resource) {
      int last = -1;
      for (size_t i = 0; i < graph.passes.size(); ++i)
        if (!graph.passes[i].culled)
          for (const BoundUse& u : graph.passes[i].outputs)
            if (u.resource == resource) last = static_cast<int>(i);
      return last;
    };

    for (size_t i = 0; i < graph.passes.size(); ++i) {
      CompiledPass& pass = graph.passes[i];
      if (pass.culled || pass.decl->type == PassType::cpu) continue;
      PassExecution& exec = result.passes[i];
      shared.current = &exec;
      const PassType type = pass.decl->type;
      if (pass.runs) {
        for (const BoundUse& in : pass.inputs) {
          exec.inputs.push_back(latest.at(in.resource));
          if (in.use == Use::host) continue;  // read from the host copy, not the GPU
          PhysicalResource& r = shared.resources.at(in.resource);
          transition(cmd, r, required_state(in.use, type, is_depth(r.desc)));
        }
      }
      for (const BoundUse& out : pass.outputs) {
        PhysicalResource& r = shared.resources.at(out.resource);
        if (pass.runs) transition(cmd, r, required_state(out.use, type, is_depth(r.desc)), !out.modifies);
      }
      if (pass.runs) {
        gpu.begin_label(cmd, pass.decl->name);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries, static_cast<uint32_t>(2 * i));
        const ParamValues params = params_of(*pass.decl);
        PassContext ctx(shared, pass, params);
        pass.decl->execute(ctx);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries,
                             static_cast<uint32_t>(2 * i + 1));
        gpu.end_label(cmd);
        exec.gpu_ms = 0.0;  // filled from the queries after the submit
      } else {
        // A skipped pass still leaves defined outputs for the passes after it.
        for (const BoundUse& out : pass.outputs) {
          if (out.modifies) continue;
          PhysicalResource& r = shared.resources.at(out.resource);
          transition(cmd, r, transfer_state(true), true);
          if (r.desc.is_buffer) {
            vkCmdFillBuffer(cmd, r.buffer.buffer, 0, VK_WHOLE_SIZE, 0);
          } else {
            VkImageSubresourceRange range{natural_aspects(r.desc.format), 0, VK_REMAINING_MIP_LEVELS, 0,
                                          VK_REMAINING_ARRAY_LAYERS};
            if (is_depth(r.desc))
              vkCmdClearDepthStencilImage(cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                          &r.desc.clear.depthStencil, 1, &range);
            else
              vkCmdClearColorImage(cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &r.desc.clear.color, 1,
                                   &range);
          }
        }
      }
      for (const BoundUse& out : pass.outputs) {
        if (!pass.runs && out.modifies) continue;
        PhysicalResource& r = shared.resources.at(out.resource);
        const int version = add_version(out.resource, r.desc, nullptr);
        exec.outputs.push_back(version);
        const bool final = last_writer_of(out.resource) == static_cast<int>(i);
        if (options.capture || (final && options.readback.count(out.resource))) read_back(r, version);
      }
    }
  } catch (...) {
    vkEndCommandBuffer(cmd);
    throw;
  }
  gpu.end_and_wait(cmd);

  std::vector<uint64_t> stamps(query_info.queryCount, 0);
  vkGetQueryPoolResults(gpu.device(), cleanup.queries, 0, query_info.queryCount, stamps.size() * 8, stamps.data(), 8,
                        VK_QUERY_RESULT_64_BIT);
  for (size_t i = 0; i < graph.passes.size(); ++i)
    if (result.passes[i].gpu_ms)
      result.passes[i].gpu_ms = double(stamps[2 * i + 1] - stamps[2 * i]) * gpu.timestamp_period_ns() / 1e6;
  for (const Staging& s : cleanup.staging) {
    if (s.version < 0) continue;
    VersionData& v = result.versions[s.version];
    const auto* begin = static_cast<const uint8_t*>(s.buffer.mapped);
    v.bytes = std::make_shared<std::vector<uint8_t>>(begin, begin + v.desc.raw_bytes());
  }
  return result;
}

}  // namespace nightcap
