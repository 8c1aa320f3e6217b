// The Vulkan device nightcap renders with: lavapipe unless a name is asked for, validation
// when NIGHTCAP_VALIDATION=1 (errors are counted so tests can fail on them), debug-utils
// labels and object names when the loader offers them, and RenderDoc's in-app API when the
// process runs under it.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace nightcap {

struct GpuError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void vk_check(VkResult result, const char* what);

// Validation messages of severity error reported in this process so far, by every device,
// including those raised while a device is destroyed (leaked objects): check it after the
// devices are gone.
uint32_t validation_errors_reported();

// A zeroed Vulkan structure with its sType set.
template <typename T>
T vk_struct(VkStructureType type) {
  T value{};
  value.sType = type;
  return value;
}

struct GpuBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  uint64_t size = 0;
  void* mapped = nullptr;  // host-visible buffers only
};

struct GpuImage {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
};

class GpuDevice {
 public:
  struct Options {
    std::string device_name;  // substring of the device name; empty: lavapipe, else the first
    bool validation = false;
  };
  explicit GpuDevice(const Options& options);
  ~GpuDevice();
  GpuDevice(const GpuDevice&) = delete;
  GpuDevice& operator=(const GpuDevice&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  bool is_cpu() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }  // lavapipe
  std::string name() const { return properties_.deviceName; }
  std::string driver() const { return driver_; }
  float timestamp_period_ns() const { return properties_.limits.timestampPeriod; }

  // `name` labels the object and its memory ("<name> memory") for debuggers and validation.
  GpuBuffer create_buffer(uint64_t size, VkBufferUsageFlags usage, bool host_visible, const std::string& name);
  void destroy(GpuBuffer& buffer);
  GpuImage create_image(const VkImageCreateInfo& info, const std::string& name);
  void destroy(GpuImage& image);

  // Placement in memory the caller allocates and frees (the graph's aliased transient memory):
  // the resource is created unbound, `placement` says what it needs, `bind` puts it at an
  // offset of a block from `allocate`. Its `memory` stays null, so destroy() frees only it.
  struct Placement {
    uint64_t size = 0, alignment = 1;  // alignment includes bufferImageGranularity
    uint32_t type = 0;                 // the device-local memory type it goes in
  };
  GpuImage create_unbound_image(const VkImageCreateInfo& info, const std::string& name);
  GpuBuffer create_unbound_buffer(uint64_t size, VkBufferUsageFlags usage, const std::string& name);
  Placement placement(const GpuImage& image) const;
  Placement placement(const GpuBuffer& buffer) const;
  // A block of at least `bytes` of memory type `type` for a frame's transient resources, and its
  // return once the frame's work is done. A returned block is handed out again to a later frame
  // that fits in it: lavapipe's device memory is the host's, and fresh memory faults on the first
  // touch of every page (about 26 000 faults a frame, most of the empty scene's frame time), where
  // a kept block's pages stay mapped. A few blocks a type are kept, the rest freed.
  struct TransientBlock {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    uint64_t bytes = 0;  // may exceed what was asked for
    uint32_t type = 0;
  };
  TransientBlock take_transient_block(uint64_t bytes, uint32_t type, const std::string& name);
  void return_transient_block(const TransientBlock& block);
  void bind(const GpuImage& image, VkDeviceMemory memory, uint64_t offset);
  void bind(const GpuBuffer& buffer, VkDeviceMemory memory, uint64_t offset);
  // A view of the image named `image_name`, named after it plus the mips, layer and aspect it
  // selects when those are not the whole image (`image_mips` levels, `image_layers` layers, every
  // aspect of info.format).
  VkImageView create_view(const VkImageViewCreateInfo& info, const std::string& image_name, uint32_t image_mips,
                          uint32_t image_layers = 1);

  // Names a Vulkan object in RenderDoc's resource list and in validation messages; does
  // nothing when VK_EXT_debug_utils is unavailable.
  void name(VkObjectType type, uint64_t handle, const std::string& name) const;
  template <typename Handle>
  void name(VkObjectType type, Handle handle, const std::string& name) const {
    this->name(type, reinterpret_cast<uint64_t>(handle), name);
  }

  VkCommandBuffer begin_commands(const std::string& name);  // one-time primary command buffer
  // A command buffer on its way through the queue, and the fence it signals.
  struct Submission {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
  };
  // Ends and submits without waiting.
  Submission submit(VkCommandBuffer cmd);
  // Waits for completion and frees the command buffer and fence.
  void wait(Submission submission);
  void end_and_wait(VkCommandBuffer cmd) { wait(submit(cmd)); }

  void begin_label(VkCommandBuffer cmd, const std::string& name) const;
  void end_label(VkCommandBuffer cmd) const;
  void push_descriptors(VkCommandBuffer cmd, VkPipelineBindPoint bind_point, VkPipelineLayout layout,
                        const std::vector<VkWriteDescriptorSet>& writes) const;

  // RenderDoc frame capture around the captured frames, when loaded into the process.
  void renderdoc_begin();
  void renderdoc_end();

 private:
  uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const;
  VkDeviceMemory allocate(uint64_t bytes, uint32_t type, const std::string& name);
  static VkBool32 VKAPI_PTR on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* self);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  std::string driver_;
  PFN_vkCmdBeginDebugUtilsLabelEXT begin_label_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT end_label_ = nullptr;
  PFN_vkSetDebugUtilsObjectNameEXT set_object_name_ = nullptr;
  PFN_vkCmdPushDescriptorSetKHR push_descriptor_set_ = nullptr;
  void* renderdoc_ = nullptr;  // RENDERDOC_API_1_1_2*

  std::mutex transient_mutex_;
  std::vector<TransientBlock> transient_free_;  // oldest first
};

}  // namespace nightcap
