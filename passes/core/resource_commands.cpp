// The Vulkan commands recorded on a frame's physical resources (resource_commands.h).
#include "passes/core/resource_commands.h"

#include <algorithm>

namespace nightcap {
namespace {

VkImageAspectFlags raw_aspect(VkFormat format, uint32_t aspect) {
  const FormatInfo f = *format_info(format);
  if (!f.is_depth) return VK_IMAGE_ASPECT_COLOR_BIT;
  return aspect == 1 ? VK_IMAGE_ASPECT_STENCIL_BIT : VK_IMAGE_ASPECT_DEPTH_BIT;
}

}  // namespace

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

void create_resource(GpuDevice& gpu, const std::string& name, PhysicalResource& r, VkImageUsageFlags usage,
                     bool bound) {
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

}  // namespace nightcap
