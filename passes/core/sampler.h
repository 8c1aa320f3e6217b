// How a shader samples an image: filters, mip sampling and wrapping, in Vulkan's terms. Passes
// declare it per sampled input (PassDecl::sampler) and scene materials carry one per texture;
// the pipeline cache makes each distinct one once.
#pragma once

#include <vulkan/vulkan.h>

namespace nightcap {

struct SamplerDesc {
  VkFilter mag_filter = VK_FILTER_LINEAR;
  VkFilter min_filter = VK_FILTER_LINEAR;
  VkSamplerMipmapMode mipmap_mode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  bool mipmaps = true;  // false for glTF NEAREST/LINEAR minification (no mip sampling)
  VkSamplerAddressMode wrap_u = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  VkSamplerAddressMode wrap_v = VK_SAMPLER_ADDRESS_MODE_REPEAT;
};

}  // namespace nightcap
