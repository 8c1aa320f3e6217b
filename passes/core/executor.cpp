#include "passes/core/executor.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <deque>
#include <utility>

#include "passes/core/execution_state.h"
#include "passes/core/frame_memory.h"
#include "passes/core/history.h"

namespace nightcap {

namespace {

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

// Creates the image or buffer of `r.desc`: with its own memory, or unbound for FrameMemory.
void create(GpuDevice& gpu, const std::string& name, PhysicalResource& r, VkImageUsageFlags usage, bool bound) {
  const ResourceDesc& d = r.desc;
  if (d.is_buffer) {
    const VkBufferUsageFlags buffer_usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                            VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    const uint64_t size = std::max<uint64_t>(d.buffer_size, 16);
    r.buffer = bound ? gpu.create_buffer(size, buffer_usage, false, name)
                     : gpu.create_unbound_buffer(size, buffer_usage, name);
    return;
  }
  auto info = vk_struct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = d.extent.depth > 1 ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  if (d.cube) info.flags |= VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
  info.format = d.format;
  info.extent = {d.extent.width, d.extent.height, d.extent.depth};
  info.mipLevels = d.extent.mips;
  info.arrayLayers = d.extent.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  // Sampling depth uses DEPTH_STENCIL_READ_ONLY_OPTIMAL, which needs attachment usage.
  if (format_info(d.format)->is_depth) info.usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  r.image = bound ? gpu.create_image(info, name) : gpu.create_unbound_image(info, name);
}

Subresources whole(const ResourceDesc& d) { return {0, d.extent.mips, 0, d.extent.layers}; }

// Every mip, layer and aspect of `from` into `to` (same description), both in transfer states.
void copy_whole(VkCommandBuffer cmd, const PhysicalResource& from, const PhysicalResource& to) {
  const ResourceDesc& d = from.desc;
  if (d.is_buffer) {
    const VkBufferCopy copy{0, 0, d.buffer_size};
    vkCmdCopyBuffer(cmd, from.buffer.buffer, to.buffer.buffer, 1, &copy);
    return;
  }
  std::vector<VkImageCopy> regions;
  for (uint32_t a = 0; a < aspect_count(*format_info(d.format)); ++a)
    for (uint32_t m = 0; m < d.extent.mips; ++m) {
      VkImageCopy region{};
      region.srcSubresource = region.dstSubresource = {raw_aspect(d.format, a), m, 0, d.extent.layers};
      region.extent = {mip_size(d.extent.width, m), mip_size(d.extent.height, m), mip_size(d.extent.depth, m)};
      regions.push_back(region);
    }
  vkCmdCopyImage(cmd, from.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to.image.image,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()), regions.data());
}

bool same_shape(const ResourceDesc& a, const ResourceDesc& b) {
  const ImageExtent &x = a.extent, &y = b.extent;
  return a.is_buffer == b.is_buffer && a.format == b.format && a.buffer_size == b.buffer_size && x.width == y.width &&
         x.height == y.height && x.depth == y.depth && x.mips == y.mips && x.layers == y.layers;
}

struct Staging {
  GpuBuffer buffer;
  int version;
};

}  // namespace

void issue(VkCommandBuffer cmd, std::map<std::string, PhysicalResource>& resources,
           const std::vector<PlannedBarrier>& planned, const std::map<std::string, AccessState>& waits) {
  if (planned.empty()) return;
  std::vector<VkImageMemoryBarrier2> images;
  std::vector<VkBufferMemoryBarrier2> buffers;
  for (const PlannedBarrier& planned_barrier : planned) {
    PlannedBarrier b = planned_barrier;
    auto wait = b.first_use ? waits.find(b.resource) : waits.end();
    if (wait != waits.end()) {
      b.plan.before.stages |= wait->second.stages;
      b.plan.before.access |= wait->second.access;
    }
    const PhysicalResource& r = resources.at(b.resource);
    const VkPipelineStageFlags2 src_stages =
        b.plan.before.stages ? b.plan.before.stages : VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT;
    if (r.desc.is_buffer) {
      auto buffer = vk_struct<VkBufferMemoryBarrier2>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2);
      buffer.srcStageMask = src_stages;
      buffer.srcAccessMask = b.plan.before.access;
      buffer.dstStageMask = b.plan.after.stages;
      buffer.dstAccessMask = b.plan.after.access;
      buffer.srcQueueFamilyIndex = buffer.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      buffer.buffer = r.buffer.buffer;
      buffer.size = VK_WHOLE_SIZE;
      buffers.push_back(buffer);
    } else {
      auto image = vk_struct<VkImageMemoryBarrier2>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2);
      image.srcStageMask = src_stages;
      image.srcAccessMask = b.plan.before.access;
      image.dstStageMask = b.plan.after.stages;
      image.dstAccessMask = b.plan.after.access;
      image.oldLayout = b.plan.before.layout;
      image.newLayout = b.plan.after.layout;
      image.srcQueueFamilyIndex = image.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      image.image = r.image.image;
      image.subresourceRange = {natural_aspects(r.desc.format), b.range.base_mip, b.range.mip_count, b.range.base_layer,
                                b.range.layer_count};
      images.push_back(image);
    }
  }
  auto dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dep.imageMemoryBarrierCount = uint32_t(images.size());
  dep.pImageMemoryBarriers = images.data();
  dep.bufferMemoryBarrierCount = uint32_t(buffers.size());
  dep.pBufferMemoryBarriers = buffers.data();
  vkCmdPipelineBarrier2(cmd, &dep);
}

void clear_to(VkCommandBuffer cmd, const PhysicalResource& r, const Subresources& range, const VkClearValue& value) {
  if (r.desc.is_buffer) {
    vkCmdFillBuffer(cmd, r.buffer.buffer, 0, VK_WHOLE_SIZE, 0);
    return;
  }
  const VkImageSubresourceRange vk_range{natural_aspects(r.desc.format), range.base_mip, range.mip_count,
                                         range.base_layer, range.layer_count};
  if (is_depth(r.desc))
    vkCmdClearDepthStencilImage(cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value.depthStencil, 1,
                                &vk_range);
  else
    vkCmdClearColorImage(cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value.color, 1, &vk_range);
}

const VersionData* Execution::final_version(const std::string& resource) const {
  for (auto it = versions.rbegin(); it != versions.rend(); ++it)
    if (it->resource == resource) return &*it;
  return nullptr;
}

// ---- execution -----------------------------------------------------------------------------

Execution execute_graph(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph,
                        const std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>& imports,
                        const ExecutionOptions& options) {
  Execution result;
  result.passes.resize(graph.passes.size());
  PassContext::Shared shared{gpu, cache, options.shaders, VK_NULL_HANDLE, {}, {}, {}, nullptr};
  std::map<std::string, int> latest;  // resource -> current version index
  // Resources holding their clear value: a skipped pass's fresh outputs, a CPU pass's empty lists.
  std::set<std::string> cleared;
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
  // previous(name) inputs of CPU passes: the bytes the pool kept from the last frame (a replay
  // imports them instead), empty when there is no valid history.
  std::map<std::string, std::string> host_pooled;  // previous(name) -> name
  for (CompiledPass& pass : graph.passes) {
    if (pass.culled || pass.decl->type != PassType::cpu) continue;
    for (BoundUse& in : pass.inputs) {
      if (!in.history || imports.count(in.resource)) continue;
      const std::string resource = history_source(in.resource);
      if (!options.history)
        throw GraphError(pass.decl->name + ": reads the previous frame's '" + resource +
                         "', but this run keeps no history");
      if (!host_pooled.emplace(in.resource, resource).second) continue;
      std::shared_ptr<const std::vector<uint8_t>> kept = options.history->find_host(resource);
      if (!kept)
        result.history_reset[resource] = "no earlier frame";
      else if (graph.settings.frame.camera_cut)
        result.history_reset[resource] = "camera cut";
      if (result.history_reset.count(resource)) kept = std::make_shared<const std::vector<uint8_t>>();
      ResourceDesc& desc = graph.resources[in.resource];
      desc.buffer_size = kept->size();
      shared.host[in.resource] = kept;
      add_version(in.resource, desc, kept);
    }
  }
  for (CompiledPass& pass : graph.passes)
    for (BoundUse& in : pass.inputs)
      if (host_pooled.count(in.resource)) in.desc = graph.resources.at(in.resource);
  // Runs a CPU pass whose inputs are on the host; its outputs become host data.
  auto run_cpu_pass = [&](size_t i) {
    CompiledPass& pass = graph.passes[i];
    PassExecution& exec = result.passes[i];
    shared.cpu_outputs.clear();
    if (pass.runs) {
      PassContext ctx(shared, pass);
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
      // Later passes saw the declared (size 0) description of a CPU buffer.
      for (size_t later = i + 1; later < graph.passes.size(); ++later)
        for (BoundUse& in : graph.passes[later].inputs)
          if (in.resource == out.resource) in.desc = out.desc;
    }
  };

  // Allocate what the GPU passes touch: transients placed together by FrameMemory, history
  // slots from the pool; a CPU pass's outputs when it has run (a buffer's size is known then).
  std::map<std::string, VkImageUsageFlags> usage;
  std::set<std::string> cpu_outputs;
  for (const CompiledPass& pass : graph.passes) {
    if (pass.culled) continue;
    if (pass.decl->type == PassType::cpu) {
      for (const BoundUse& u : pass.outputs) cpu_outputs.insert(u.resource);
      continue;
    }
    for (const BoundUse& u : pass.inputs) usage[u.resource] |= usage_for(u.use);
    for (const BoundUse& u : pass.outputs) usage[u.resource] |= usage_for(u.use);
  }
  FrameMemory memory(gpu);
  // A submitted part of the frame, and how many staging buffers it fills.
  struct InFlight {
    GpuDevice::Submission submission;
    size_t staging_end;
  };
  struct Cleanup {
    GpuDevice& gpu;
    PassContext::Shared& shared;
    std::vector<Staging> staging;
    VkQueryPool queries = VK_NULL_HANDLE;
    std::deque<InFlight> in_flight;
    ~Cleanup() {
      // Nothing may be destroyed while the queue still uses it (after an exception).
      for (InFlight& part : in_flight) {
        vkWaitForFences(gpu.device(), 1, &part.submission.fence, VK_TRUE, UINT64_MAX);
        vkDestroyFence(gpu.device(), part.submission.fence, nullptr);
      }
      for (auto& [name, r] : shared.resources) {
        for (auto& [key, view] : r.views) vkDestroyImageView(gpu.device(), view, nullptr);
        if (!r.owned) continue;
        gpu.destroy(r.image);
        gpu.destroy(r.buffer);
      }
      for (Staging& s : staging) gpu.destroy(s.buffer);
      if (queries) vkDestroyQueryPool(gpu.device(), queries, nullptr);
    }
  } cleanup{gpu, shared, {}, VK_NULL_HANDLE, {}};
  // previous(name) inputs the history pool supplies (a replay imports them instead).
  std::map<std::string, std::string> pooled;  // previous(name) -> name
  for (const std::string& name : graph.history) pooled[name] = history_source(name);
  if (!options.history)
    for (const CompiledPass& pass : graph.passes)
      for (const BoundUse& in : pass.inputs)
        if (pooled.count(in.resource))
          throw GraphError(pass.decl->name + ": reads the previous frame's '" + pooled.at(in.resource) +
                           "', but this run keeps no history");
  std::map<std::string, PhysicalResource*> transients;
  for (const auto& [name, flags] : usage) {
    // A resource no step of the plan touches (an input of a skipped pass only) needs no memory.
    if (pooled.count(name) || cpu_outputs.count(name) || !graph.lifetimes.count(name)) continue;
    PhysicalResource& r = shared.resources[name];
    r.desc = graph.resources.at(name);
    create(gpu, name, r, flags, false);
    transients[name] = &r;
  }
  memory.place(transients, graph.lifetimes, options.alias_memory);
  result.memory_bytes = memory.bytes();
  result.memory_bytes_without_aliasing = memory.bytes_without_aliasing();
  std::map<std::string, HistorySlot*> slots;  // previous(name) -> its slot in the pool
  std::set<std::string> cleared_slots;        // those this frame cleared
  for (const auto& [name, resource] : pooled) {
    const ResourceDesc& desc = graph.resources.at(name);
    HistorySlot* slot = options.history->find(resource);
    const bool reshaped = slot && !same_shape(slot->resource.desc, desc);
    if (!slot || reshaped || slot->usage != usage[name]) {
      HistorySlot fresh;
      fresh.resource.desc = desc;
      fresh.usage = usage[name];
      create(gpu, name, fresh.resource, fresh.usage, true);
      slot = &options.history->replace(resource, std::move(fresh));
    }
    if (!slot->filled)
      result.history_reset[resource] = reshaped ? "size changed" : "no earlier frame";
    else if (graph.settings.frame.camera_cut)
      result.history_reset[resource] = "camera cut";
    PhysicalResource& r = shared.resources[name] = slot->resource;
    r.owned = false;
    slots[name] = slot;
    const GpuDevice::Placement held = r.desc.is_buffer ? gpu.placement(r.buffer) : gpu.placement(r.image);
    result.memory_bytes += held.size;
    result.memory_bytes_without_aliasing += held.size;
  }
  auto issue_step = [&](const std::vector<PlannedBarrier>& planned) {
    issue(shared.cmd, shared.resources, planned, memory.waits());
  };

  auto query_info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  query_info.queryCount = static_cast<uint32_t>(2 * graph.passes.size() + 2);
  vk_check(vkCreateQueryPool(gpu.device(), &query_info, nullptr, &cleanup.queries), "vkCreateQueryPool");
  gpu.name(VK_OBJECT_TYPE_QUERY_POOL, cleanup.queries, "pass timestamps");
  vkResetQueryPool(gpu.device(), cleanup.queries, 0, query_info.queryCount);

  const std::string frame_name =
      options.name.empty() ? "frame " + std::to_string(graph.settings.frame.frame_index) : options.name;
  shared.cmd = gpu.begin_commands(frame_name);
  result.submits = 1;
  // Copies the staging buffers up to `end` into their versions (after a wait for the GPU).
  size_t harvested = 0;
  auto harvest = [&](size_t end) {
    for (; harvested < end; ++harvested) {
      const Staging& s = cleanup.staging[harvested];
      if (s.version < 0) continue;
      VersionData& v = result.versions[s.version];
      const auto* begin = static_cast<const uint8_t*>(s.buffer.mapped);
      v.bytes = std::make_shared<std::vector<uint8_t>>(begin, begin + v.desc.raw_bytes());
      if (options.on_read_back) options.on_read_back(v);
    }
  };
  auto wait_oldest = [&] {
    InFlight part = cleanup.in_flight.front();
    cleanup.in_flight.pop_front();
    gpu.wait(part.submission);
    harvest(part.staging_end);
  };
  // Submits what is recorded so far; with `wait_all`, waits for it and every earlier part, so
  // that everything read back so far is on the host.
  auto submit = [&](bool wait_all) {
    cleanup.in_flight.push_back({gpu.submit(std::exchange(shared.cmd, VK_NULL_HANDLE)), cleanup.staging.size()});
    while (cleanup.in_flight.size() > (wait_all ? 0 : 1)) wait_oldest();
  };
  try {
    auto upload = [&](const std::string& name) {
      PhysicalResource& r = shared.resources.at(name);
      auto host = shared.host.find(name);
      if (host == shared.host.end()) throw GraphError("no bytes were given for imported '" + name + "'");
      const std::vector<uint8_t>& bytes = *host->second;
      GpuBuffer staging = gpu.create_buffer(std::max<size_t>(bytes.size(), 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                                            "upload " + name);
      if (!bytes.empty()) std::memcpy(staging.mapped, bytes.data(), bytes.size());
      cleanup.staging.push_back({staging, -1});
      if (r.desc.is_buffer) {
        if (!bytes.empty()) {
          VkBufferCopy copy{0, 0, bytes.size()};
          vkCmdCopyBuffer(shared.cmd, staging.buffer, r.buffer.buffer, 1, &copy);
        }
      } else {
        auto regions = raw_copy_regions(r.desc);
        vkCmdCopyBufferToImage(shared.cmd, staging.buffer, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                               static_cast<uint32_t>(regions.size()), regions.data());
      }
    };
    // `what`: the resource and the pass that wrote this version, e.g. "gbuffer.normal from gbuffer.opaque".
    auto read_back = [&](PhysicalResource& r, int version, const std::string& what) {
      GpuBuffer staging = gpu.create_buffer(std::max<uint64_t>(r.desc.raw_bytes(), 16),
                                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "readback " + what);
      cleanup.staging.push_back({staging, version});
      if (r.desc.is_buffer) {
        if (r.desc.buffer_size) {
          VkBufferCopy copy{0, 0, r.desc.buffer_size};
          vkCmdCopyBuffer(shared.cmd, r.buffer.buffer, staging.buffer, 1, &copy);
        }
      } else {
        auto regions = raw_copy_regions(r.desc);
        vkCmdCopyImageToBuffer(shared.cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer,
                               static_cast<uint32_t>(regions.size()), regions.data());
      }
    };
    // A NaN in one texel of what the pass wrote, through a staging buffer as uploads are.
    auto inject_nan = [&](const NanInjection& nan) {
      const PhysicalResource& r = shared.resources.at(nan.resource);
      const std::vector<uint8_t> texel = quiet_nan_texel(*format_info(r.desc.format));
      GpuBuffer staging = gpu.create_buffer(std::max<size_t>(texel.size(), 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                                            "NaN for " + nan.resource + " after " + nan.pass);
      std::memcpy(staging.mapped, texel.data(), texel.size());
      cleanup.staging.push_back({staging, -1});
      VkBufferImageCopy region{};
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageOffset = {int32_t(nan.x), int32_t(nan.y), 0};
      region.imageExtent = {1, 1, 1};
      vkCmdCopyBufferToImage(shared.cmd, staging.buffer, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                             &region);
    };
    // Uploads of imported data the GPU reads.
    issue_step(graph.before_uploads);
    for (const std::string& name : graph.uploads) upload(name);
    // The previous frame's values, or the declared initial value where there is no valid one.
    // A slot with valid history is already where the plan's clear barriers would leave it.
    // A slot that holds the clear value already needs no clear.
    auto starts_cleared = [&](const std::string& name) {
      const HistorySlot& slot = *slots.at(name);
      return (result.history_reset.count(pooled.at(name)) || slot.at_clear_value) && !slot.holds_clear_value;
    };
    std::vector<PlannedBarrier> reset;
    for (const PlannedBarrier& b : graph.before_history_clears)
      if (starts_cleared(b.resource)) reset.push_back(b);
    issue_step(reset);
    std::map<std::string, int> history_versions;
    for (const auto& [name, resource] : pooled) {
      PhysicalResource& r = shared.resources.at(name);
      if (starts_cleared(name)) {
        clear_to(shared.cmd, r, whole(r.desc), r.desc.clear);
        cleared_slots.insert(name);
      }
      history_versions[name] = add_version(name, r.desc, nullptr);
    }
    issue_step(graph.before_history_readback);
    if (graph.settings.capture)
      for (const auto& [name, version] : history_versions) read_back(shared.resources.at(name), version, name);

    for (size_t i = 0; i < graph.passes.size(); ++i) {
      CompiledPass& pass = graph.passes[i];
      if (pass.culled) continue;
      PassExecution& exec = result.passes[i];
      shared.current = &exec;
      if (pass.decl->type == PassType::cpu) {
        for (const BoundUse& in : pass.inputs)
          if (std::find(exec.inputs.begin(), exec.inputs.end(), latest.at(in.resource)) == exec.inputs.end())
            exec.inputs.push_back(latest.at(in.resource));
        // A version a GPU pass computed has no host bytes until the frame so far has run.
        const bool needs_gpu_results =
            pass.runs && std::any_of(pass.inputs.begin(), pass.inputs.end(), [&](const BoundUse& in) {
              return !result.versions[latest.at(in.resource)].bytes;
            });
        if (needs_gpu_results) {
          // The frame so far runs now, so this pass can read what it computed.
          issue_step(pass.sync.before_host_reads);
          for (const std::string& resource : pass.sync.host_reads)
            read_back(shared.resources.at(resource), latest.at(resource), resource + " for " + pass.decl->name);
          submit(true);
          shared.cmd = gpu.begin_commands(frame_name + " after " + pass.decl->name);
          ++result.submits;
          for (const BoundUse& in : pass.inputs) {
            shared.host[in.resource] = result.versions[latest.at(in.resource)].bytes;
            if (!shared.host[in.resource])
              throw GraphError(pass.decl->name + ": '" + in.resource + "' was not copied to the host for it");
          }
        }
        run_cpu_pass(i);
        for (const BoundUse& out : pass.outputs)
          if (!pass.runs || (out.desc.is_buffer && shared.host.at(out.resource)->empty()))
            cleared.insert(out.resource);
          else
            cleared.erase(out.resource);
        for (const std::string& name : pass.sync.uploads) {
          PhysicalResource& r = shared.resources[name];
          r.desc = graph.resources.at(name);
          create(gpu, name, r, usage[name], true);
        }
        issue_step(pass.sync.before_uploads);
        for (const std::string& name : pass.sync.uploads) upload(name);
        continue;
      }
      // A list a CPU pass left empty is known only now: a pass it skips either modifies its
      // outputs alone, so leaving them as they are is all that is left to do, or leaves its fresh
      // outputs cleared for passes that skip too (compile_graph checks); its planned barriers
      // are still issued, and the plan after it holds. A kept pass (a replay) runs whatever its
      // inputs.
      const bool planned_to_run = pass.runs;
      const auto& keep = graph.settings.keep;
      if (pass.runs && !pass.decl->cleared_skips.empty() &&
          std::find(keep.begin(), keep.end(), pass.decl->name) == keep.end())
        if (const auto* skip = pass.decl->cleared_skip(cleared, pass.params)) {
          pass.runs = false;
          // Cleared outputs are not what it computes: nothing for a replay to check.
          pass.inputs_known = !pass.clears_if_skipped;
          pass.reason = skip->reason();
          if (pass.clears_if_skipped) pass.reason += "; its outputs left cleared: every pass that reads them skips too";
        }
      // A skipped pass still leaves defined outputs for the passes after it, and a pass that
      // writes part of a fresh output leaves the rest defined.
      issue_step(pass.sync.before_clears);
      for (const PlannedClear& clear : pass.sync.clears)
        if (!clear.only_if_skipped || !pass.runs)
          clear_to(shared.cmd, shared.resources.at(clear.resource), clear.range, clear.value);
      // A resource used in two ways (two mips, storage and index buffer) is one input version.
      // A pass skipped for cleared inputs records them too: a replay runs it on them.
      if (pass.runs || pass.inputs_known)
        for (const BoundUse& in : pass.inputs)
          if (std::find(exec.inputs.begin(), exec.inputs.end(), latest.at(in.resource)) == exec.inputs.end())
            exec.inputs.push_back(latest.at(in.resource));
      if (planned_to_run) issue_step(pass.sync.before_pass);
      if (pass.runs) {
        gpu.begin_label(shared.cmd, pass.decl->name);
        vkCmdWriteTimestamp2(shared.cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries,
                             static_cast<uint32_t>(2 * i));
        PassContext ctx(shared, pass);
        pass.decl->execute(ctx);
        vkCmdWriteTimestamp2(shared.cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries,
                             static_cast<uint32_t>(2 * i + 1));
        gpu.end_label(shared.cmd);
        exec.gpu_ms = 0.0;  // filled from the queries after the submit
      }
      if (planned_to_run) issue_step(pass.sync.before_injections);
      if (pass.runs)
        for (const NanInjection& nan : pass.sync.injections) inject_nan(nan);
      std::map<std::string, int> written;
      for (const BoundUse& out : pass.outputs) {
        auto folded = pass.folded.find(out.resource);
        if (!pass.runs && out.modifies && folded == pass.folded.end()) {
          // Skipped or folded for what its inputs hold, it left them as they were: the replay
          // checks that.
          if (pass.inputs_known) exec.outputs.push_back(latest.at(out.resource));
          continue;
        }
        // A skipped pass's output that nothing reads has no memory (plan_synchronisation).
        written[out.resource] = add_version(out.resource, graph.resources.at(out.resource), nullptr);
        exec.outputs.push_back(written[out.resource]);
        if (!pass.runs && folded == pass.folded.end())
          cleared.insert(out.resource);
        else
          cleared.erase(out.resource);
      }
      issue_step(pass.sync.before_readback);
      for (const std::string& resource : pass.sync.readback)
        if (written.count(resource))
          read_back(shared.resources.at(resource), written.at(resource), resource + " from " + pass.decl->name);
      if (options.on_read_back && !pass.sync.readback.empty() && i + 1 < graph.passes.size()) {
        submit(false);
        shared.cmd = gpu.begin_commands(frame_name + " after " + pass.decl->name);
        ++result.submits;
      }
    }
    // This frame's final values are the next frame's history.
    issue_step(graph.before_history_copy);
    for (const auto& [name, resource] : pooled)
      if (!graph.history_at_clear_value.count(name))
        copy_whole(shared.cmd, shared.resources.at(resource), shared.resources.at(name));
  } catch (...) {
    if (shared.cmd) vkEndCommandBuffer(shared.cmd);
    throw;
  }
  submit(true);
  for (const auto& [name, slot] : slots) {
    slot->filled = true;
    slot->at_clear_value = graph.history_at_clear_value.count(name) > 0;
    slot->holds_clear_value = slot->at_clear_value && (slot->holds_clear_value || cleared_slots.count(name));
  }
  for (const auto& [name, resource] : host_pooled) {
    auto written = shared.host.find(resource);
    options.history->keep_host(resource, written != shared.host.end() && written->second
                                             ? written->second
                                             : std::make_shared<const std::vector<uint8_t>>());
  }

  // Only a pass that ran wrote its two timestamps: asking for the pool's every query would answer
  // VK_NOT_READY for the others, and waiting on them would never end.
  for (size_t i = 0; i < graph.passes.size(); ++i) {
    if (!result.passes[i].gpu_ms) continue;
    uint64_t stamps[2] = {};
    vk_check(vkGetQueryPoolResults(gpu.device(), cleanup.queries, static_cast<uint32_t>(2 * i), 2, sizeof stamps,
                                   stamps, sizeof stamps[0], VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
             "vkGetQueryPoolResults");
    result.passes[i].gpu_ms = double(stamps[1] - stamps[0]) * gpu.timestamp_period_ns() / 1e6;
  }
  return result;
}

}  // namespace nightcap
