#include "passes/core/device.h"

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "passes/core/format.h"

#ifdef NIGHTCAP_SANITIZE_BUILD
// Leaks of Debian 12's libraries that sanitizer builds report, and their reasons. LeakSanitizer
// asks the program for suppressions through this hook; every nightcap executable links this file,
// so every test and CLI run of a sanitizer build has them.
// - The Khronos validation layer (1.3.239) leaks blocks of its own: with synchronization
//   validation on, every process that creates a device with the layer ends with leaks allocated
//   in libVkLayer_khronos_validation.so alone (all indirect: a cycle), and the same tests leak
//   nothing without the layer. Objects nightcap leaks are reported by the layer itself when the
//   device is destroyed and fail the command (tests/unit/validation_test.cpp).
// - libedit (3.1) copies the name and help of a function bound with EL_ADDFN (inspect's Tab
//   completion) with wcsdup and never frees them: 240 bytes, once. nightcap calls no wcsdup.
// - lavapipe (Mesa 22.3, LLVM 15) leaks 11 488 bytes in six blocks, a cycle, for each compute
//   pipeline with nested branches in a loop that holds a barrier (lights.cluster's four; removing
//   one branch of docs/reproducers/lights_cluster_leak.comp removes the leak). Five blocks are
//   allocated in libvulkan_lvp.so, one in LLVM's JIT as the driver registers the code's unwind
//   tables. A Vulkan object nightcap leaks is the layer's to report (above), and nightcap's own
//   allocations never have the driver on their stack.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libVkLayer_khronos_validation.so\n"
         "leak:wcsdup\n"
         "leak:libvulkan_lvp.so\n"
         "leak:RTDyldMemoryManager::registerEHFrames\n";
}

// LeakSanitizer's tracer used to die at exit now and then ("Tracer caught signal 11", about one
// sanitizer suite in eight). GCC 12's runtime (as LLVM's up to 16) intercepts __tls_get_addr and,
// for a dynamic TLS block that starts 16 bytes into a page, assumes glibc 2.19's layout and reads
// the two words before it as the block's start and size; glibc 2.25 and later put no such header
// there, so a block that lands at that offset by chance hands the tracer a garbage range to scan.
// lavapipe's Mesa and LLVM give every thread they start dynamic TLS blocks. Without the
// interception the blocks are heap blocks like any other, found through each thread's vector of
// them (docs/testing.md).
extern "C" const char* __asan_default_options() { return "intercept_tls_get_addr=0"; }
#endif

namespace nightcap {
namespace {

std::atomic<uint32_t> g_validation_errors{0};

// The in-app API's function table (renderdoc_app.h, API 1.1.2): only the frame-capture entry
// points are called, so the rest are opaque slots that keep the layout.
struct RenderDocApi {
  void* unused_before_start[19];
  void (*StartFrameCapture)(void* device, void* window);
  uint32_t (*IsFrameCapturing)();
  uint32_t (*EndFrameCapture)(void* device, void* window);
};
constexpr int kRenderDocApi_1_1_2 = 10102;
using RenderDocGetApi = int (*)(int version, void** api);

void* load_renderdoc() {
  // RTLD_NOLOAD: only when renderdoccmd (or the UI) injected it; never load it ourselves.
  void* library = dlopen("librenderdoc.so", RTLD_NOW | RTLD_NOLOAD);
  if (!library) return nullptr;
  auto get_api = reinterpret_cast<RenderDocGetApi>(dlsym(library, "RENDERDOC_GetAPI"));
  void* api = nullptr;
  if (!get_api || get_api(kRenderDocApi_1_1_2, &api) != 1) return nullptr;
  return api;
}

// What a vkEnumerate* call lists: the count, then the items, asked again while the list grew
// between the two calls (VK_INCOMPLETE); any error throws.
template <typename Item, typename Call>
std::vector<Item> enumerate(const char* what, Call call) {
  std::vector<Item> items;
  VkResult result = VK_INCOMPLETE;
  while (result == VK_INCOMPLETE) {
    uint32_t count = 0;
    vk_check(call(&count, nullptr), what);
    items.resize(count);
    result = call(&count, items.data());
    items.resize(count);
  }
  vk_check(result, what);
  return items;
}

bool has_layer(const char* name) {
  for (const auto& layer :
       enumerate<VkLayerProperties>("vkEnumerateInstanceLayerProperties", vkEnumerateInstanceLayerProperties))
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

bool has_instance_extension(const char* name) {
  const auto extensions = enumerate<VkExtensionProperties>(
      "vkEnumerateInstanceExtensionProperties", [](uint32_t* count, VkExtensionProperties* items) {
        return vkEnumerateInstanceExtensionProperties(nullptr, count, items);
      });
  for (const auto& e : extensions)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

// LeakSanitizer checks at exit, after the Vulkan loader has unloaded the driver and the layers:
// what their globals still pointed to then looks leaked (lavapipe: 112 bytes), from a module that
// no longer has a name, so no suppression can match it. Keeping those modules loaded in sanitizer
// builds leaves their memory reachable, and a real leak of theirs would still be reported under
// the module's name. The project's own code is unaffected: it is not in these modules.
void keep_vulkan_modules_loaded() {
#ifdef NIGHTCAP_SANITIZE_BUILD
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) {
        const std::string path = info->dlpi_name ? info->dlpi_name : "";
        const std::string file = path.substr(path.find_last_of('/') + 1);
        if (file.rfind("libvulkan_", 0) == 0 || file.rfind("libVkLayer_", 0) == 0)
          dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        return 0;
      },
      nullptr);
#endif
}

}  // namespace

uint32_t validation_errors_reported() { return g_validation_errors.load(); }

void vk_check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw GpuError(std::string("Vulkan: ") + what + " failed (VkResult " + std::to_string(result) + ")");
}

VkBool32 VKAPI_PTR GpuDevice::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    g_validation_errors++;
    std::cerr << "validation error: " << data->pMessage << "\n";
  } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    std::cerr << "validation warning: " << data->pMessage << "\n";
  }
  return VK_FALSE;
}

GpuDevice::GpuDevice(const Options& options) {
  auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "nightcap";
  app.apiVersion = VK_API_VERSION_1_3;

  std::vector<const char*> layers, extensions;
  const bool debug_utils = has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (options.validation) {
    if (!has_layer("VK_LAYER_KHRONOS_validation"))
      throw GpuError("validation requested but VK_LAYER_KHRONOS_validation is not installed");
    // Without debug utils the layer's errors would reach no callback and count as none.
    if (!debug_utils)
      throw GpuError("validation requested but " VK_EXT_DEBUG_UTILS_EXTENSION_NAME
                     " is not available: its errors could not be counted");
    layers.push_back("VK_LAYER_KHRONOS_validation");
  }
  auto messenger_info =
      vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  messenger_info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
  messenger_info.messageType =
      VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
  messenger_info.pfnUserCallback = &GpuDevice::on_message;

  auto instance_info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  instance_info.pApplicationInfo = &app;
  instance_info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  instance_info.ppEnabledLayerNames = layers.data();
  instance_info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  instance_info.ppEnabledExtensionNames = extensions.data();
  // Synchronization validation too: it reports hazards between commands (a missing or too
  // narrow barrier) as errors. Debian's layer (1.3.239) checks transfers and shader accesses but
  // not dynamic-rendering attachments.
  const VkValidationFeatureEnableEXT enabled_features[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  auto validation_features = vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  validation_features.enabledValidationFeatureCount = 1;
  validation_features.pEnabledValidationFeatures = enabled_features;
  validation_features.pNext = &messenger_info;
  if (options.validation) instance_info.pNext = &validation_features;
  vk_check(vkCreateInstance(&instance_info, nullptr, &instance_), "vkCreateInstance");

  if (options.validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw GpuError("validation requested but vkCreateDebugUtilsMessengerEXT is missing");
    vk_check(create(instance_, &messenger_info, nullptr, &messenger_), "create messenger");
  }
  if (debug_utils) {
    begin_label_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    end_label_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
    set_object_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
  }

  const auto physicals = enumerate<VkPhysicalDevice>(
      "vkEnumeratePhysicalDevices",
      [&](uint32_t* count, VkPhysicalDevice* items) { return vkEnumeratePhysicalDevices(instance_, count, items); });
  std::string available;
  for (VkPhysicalDevice candidate : physicals) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(candidate, &props);
    available += std::string(available.empty() ? "" : ", ") + props.deviceName;
    const std::string name = props.deviceName;
    const bool wanted = options.device_name.empty() ? name.find("llvmpipe") != std::string::npos
                                                    : name.find(options.device_name) != std::string::npos;
    if (wanted && props.apiVersion >= VK_API_VERSION_1_3) {
      physical_ = candidate;
      break;
    }
  }
  if (!physical_ && options.device_name.empty() && !physicals.empty()) physical_ = physicals[0];
  if (!physical_)
    throw GpuError("--device '" + options.device_name +
                   "': no Vulkan 1.3 device matches (available: " + (available.empty() ? "none" : available) + ")");
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  auto driver_props = vk_struct<VkPhysicalDeviceDriverProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
  auto props2 = vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
  props2.pNext = &driver_props;
  vkGetPhysicalDeviceProperties2(physical_, &props2);
  driver_ = std::string(driver_props.driverName) + " " + driver_props.driverInfo;

  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, families.data());
  bool found = false;
  for (uint32_t i = 0; i < family_count; ++i) {
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0) {
      queue_family_ = i;
      found = true;
      break;
    }
  }
  if (!found) throw GpuError(name() + ": no graphics+compute queue with timestamps");

  float priority = 1.0f;
  auto queue_info = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  auto features13 = vk_struct<VkPhysicalDeviceVulkan13Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  features13.dynamicRendering = VK_TRUE;
  features13.synchronization2 = VK_TRUE;
  features13.maintenance4 = VK_TRUE;  // glslang's SPIR-V 1.6 declares workgroup sizes with LocalSizeId
  auto features12 = vk_struct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
  features12.pNext = &features13;
  features12.hostQueryReset = VK_TRUE;
  features12.scalarBlockLayout = VK_TRUE;
  auto features11 = vk_struct<VkPhysicalDeviceVulkan11Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES);
  features11.pNext = &features12;
  features11.shaderDrawParameters = VK_TRUE;
  auto features = vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  features.pNext = &features11;
  features.features.samplerAnisotropy = VK_FALSE;
  features.features.fragmentStoresAndAtomics = VK_TRUE;
  features.features.depthBiasClamp = VK_TRUE;  // RasterState's depth bias may be limited
  features.features.shaderStorageImageWriteWithoutFormat = VK_TRUE;
  features.features.imageCubeArray = VK_TRUE;  // the reflection probes' faces, a cube per probe

  const char* device_extensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  auto device_info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  device_info.pNext = &features;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.enabledExtensionCount = 1;
  device_info.ppEnabledExtensionNames = device_extensions;
  vk_check(vkCreateDevice(physical_, &device_info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  name(VK_OBJECT_TYPE_QUEUE, queue_, "nightcap queue");
  push_descriptor_set_ =
      reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));

  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.queueFamilyIndex = queue_family_;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  vk_check(vkCreateCommandPool(device_, &pool_info, nullptr, &pool_), "vkCreateCommandPool");
  name(VK_OBJECT_TYPE_COMMAND_POOL, pool_, "nightcap commands");
  renderdoc_ = load_renderdoc();
  keep_vulkan_modules_loaded();
}

GpuDevice::~GpuDevice() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    for (const TransientBlock& block : transient_free_) vkFreeMemory(device_, block.memory, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

uint32_t GpuDevice::memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw GpuError("no Vulkan memory type with the required properties");
}

void GpuDevice::name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!set_object_name_) return;
  auto info = vk_struct<VkDebugUtilsObjectNameInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT);
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  vk_check(set_object_name_(device_, &info), "vkSetDebugUtilsObjectNameEXT");
}

GpuBuffer GpuDevice::create_buffer(uint64_t size, VkBufferUsageFlags usage, bool host_visible,
                                   const std::string& name) {
  GpuBuffer result = create_unbound_buffer(size, usage, name);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, result.buffer, &req);
  const uint32_t type = memory_type(
      req.memoryTypeBits, host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                       : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  result.memory = allocate(req.size, type, name + " memory");
  bind(result, result.memory, 0);
  if (host_visible) vk_check(vkMapMemory(device_, result.memory, 0, VK_WHOLE_SIZE, 0, &result.mapped), "vkMapMemory");
  return result;
}

void GpuDevice::destroy(GpuBuffer& buffer) {
  if (buffer.buffer) vkDestroyBuffer(device_, buffer.buffer, nullptr);
  if (buffer.memory) vkFreeMemory(device_, buffer.memory, nullptr);
  buffer = {};
}

GpuImage GpuDevice::create_image(const VkImageCreateInfo& info, const std::string& name) {
  GpuImage result = create_unbound_image(info, name);
  const Placement needs = placement(result);
  result.memory = allocate(needs.size, needs.type, name + " memory");
  bind(result, result.memory, 0);
  return result;
}

GpuImage GpuDevice::create_unbound_image(const VkImageCreateInfo& info, const std::string& name) {
  GpuImage result;
  vk_check(vkCreateImage(device_, &info, nullptr, &result.image), "vkCreateImage");
  this->name(VK_OBJECT_TYPE_IMAGE, result.image, name);
  return result;
}

GpuBuffer GpuDevice::create_unbound_buffer(uint64_t size, VkBufferUsageFlags usage, const std::string& name) {
  GpuBuffer result;
  result.size = size;
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = std::max<uint64_t>(size, 16);
  info.usage = usage;
  vk_check(vkCreateBuffer(device_, &info, nullptr, &result.buffer), "vkCreateBuffer");
  this->name(VK_OBJECT_TYPE_BUFFER, result.buffer, name);
  return result;
}

namespace {

GpuDevice::Placement placement_of(const VkMemoryRequirements& req, uint32_t type, uint64_t granularity) {
  // Buffers and optimal-tiling images share blocks, so every offset keeps them a granule apart.
  return {req.size, std::max<uint64_t>(req.alignment, granularity), type};
}

}  // namespace

GpuDevice::Placement GpuDevice::placement(const GpuImage& image) const {
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device_, image.image, &req);
  return placement_of(req, memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT),
                      properties_.limits.bufferImageGranularity);
}

GpuDevice::Placement GpuDevice::placement(const GpuBuffer& buffer) const {
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer.buffer, &req);
  return placement_of(req, memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT),
                      properties_.limits.bufferImageGranularity);
}

VkDeviceMemory GpuDevice::allocate(uint64_t bytes, uint32_t type, const std::string& name) {
  auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = bytes;
  alloc.memoryTypeIndex = type;
  VkDeviceMemory memory;
  vk_check(vkAllocateMemory(device_, &alloc, nullptr, &memory), "vkAllocateMemory");
  this->name(VK_OBJECT_TYPE_DEVICE_MEMORY, memory, name);
  return memory;
}

// Free blocks kept per memory type; a frame places its transients in one block a type.
constexpr size_t kKeptTransientBlocks = 4;

GpuDevice::TransientBlock GpuDevice::take_transient_block(uint64_t bytes, uint32_t type, const std::string& name) {
  std::lock_guard lock(transient_mutex_);
  // The smallest kept block it fits, unless that would hold more than twice what it needs.
  auto best = transient_free_.end();
  for (auto it = transient_free_.begin(); it != transient_free_.end(); ++it)
    if (it->type == type && it->bytes >= bytes && it->bytes <= 2 * bytes &&
        (best == transient_free_.end() || it->bytes < best->bytes))
      best = it;
  if (best == transient_free_.end()) return {allocate(bytes, type, name), bytes, type};
  const TransientBlock block = *best;
  transient_free_.erase(best);
  this->name(VK_OBJECT_TYPE_DEVICE_MEMORY, block.memory, name);
  return block;
}

void GpuDevice::return_transient_block(const TransientBlock& block) {
  std::lock_guard lock(transient_mutex_);
  transient_free_.push_back(block);
  size_t kept = 0;
  for (const TransientBlock& b : transient_free_) kept += b.type == block.type;
  if (kept <= kKeptTransientBlocks) return;
  const auto oldest = std::find_if(transient_free_.begin(), transient_free_.end(),
                                   [&](const TransientBlock& b) { return b.type == block.type; });
  vkFreeMemory(device_, oldest->memory, nullptr);
  transient_free_.erase(oldest);
}

void GpuDevice::bind(const GpuImage& image, VkDeviceMemory memory, uint64_t offset) {
  vk_check(vkBindImageMemory(device_, image.image, memory, offset), "vkBindImageMemory");
}

void GpuDevice::bind(const GpuBuffer& buffer, VkDeviceMemory memory, uint64_t offset) {
  vk_check(vkBindBufferMemory(device_, buffer.buffer, memory, offset), "vkBindBufferMemory");
}

void GpuDevice::destroy(GpuImage& image) {
  if (image.image) vkDestroyImage(device_, image.image, nullptr);
  if (image.memory) vkFreeMemory(device_, image.memory, nullptr);
  image = {};
}

VkImageView GpuDevice::create_view(const VkImageViewCreateInfo& info, const std::string& image_name,
                                   uint32_t image_mips, uint32_t image_layers) {
  VkImageView view;
  vk_check(vkCreateImageView(device_, &info, nullptr, &view), "vkCreateImageView");
  const VkImageSubresourceRange& range = info.subresourceRange;
  std::string label = image_name;
  // Only a depth-stencil image has an aspect a view can leave out.
  const std::optional<FormatInfo> format = format_info(info.format);
  if (format && format->has_stencil && range.aspectMask == VK_IMAGE_ASPECT_DEPTH_BIT) label += " depth";
  if (format && format->has_stencil && range.aspectMask == VK_IMAGE_ASPECT_STENCIL_BIT) label += " stencil";
  if (range.levelCount == 1 && image_mips > 1) {
    label += " mip " + std::to_string(range.baseMipLevel);
  } else if (range.baseMipLevel != 0 || range.levelCount < image_mips) {
    label +=
        " mips " + std::to_string(range.baseMipLevel) + "-" + std::to_string(range.baseMipLevel + range.levelCount - 1);
  }
  if (range.layerCount == 1 && image_layers > 1) label += " layer " + std::to_string(range.baseArrayLayer);
  name(VK_OBJECT_TYPE_IMAGE_VIEW, view, label);
  return view;
}

VkCommandBuffer GpuDevice::begin_commands(const std::string& name) {
  auto info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  info.commandPool = pool_;
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  VkCommandBuffer cmd;
  vk_check(vkAllocateCommandBuffers(device_, &info, &cmd), "vkAllocateCommandBuffers");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk_check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  // After begin: RenderDoc starts a fresh record for the buffer there and drops an earlier name.
  this->name(VK_OBJECT_TYPE_COMMAND_BUFFER, cmd, name);
  return cmd;
}

GpuDevice::Submission GpuDevice::submit(VkCommandBuffer cmd) {
  Submission submission{cmd, VK_NULL_HANDLE};
  VkResult result = vkEndCommandBuffer(cmd);
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  if (result == VK_SUCCESS) result = vkCreateFence(device_, &fence_info, nullptr, &submission.fence);
  if (result == VK_SUCCESS) {
    name(VK_OBJECT_TYPE_FENCE, submission.fence, "submit fence");
    auto info = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    info.commandBufferCount = 1;
    info.pCommandBuffers = &cmd;
    result = vkQueueSubmit(queue_, 1, &info, submission.fence);
  }
  if (result != VK_SUCCESS) {
    if (submission.fence) vkDestroyFence(device_, submission.fence, nullptr);
    vkFreeCommandBuffers(device_, pool_, 1, &cmd);
    vk_check(result, "vkEndCommandBuffer/vkQueueSubmit");
  }
  return submission;
}

void GpuDevice::wait(Submission submission) {
  const VkResult result = vkWaitForFences(device_, 1, &submission.fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(device_, submission.fence, nullptr);
  vkFreeCommandBuffers(device_, pool_, 1, &submission.cmd);
  vk_check(result, "vkWaitForFences");
}

void GpuDevice::begin_label(VkCommandBuffer cmd, const std::string& name) const {
  if (!begin_label_) return;
  auto label = vk_struct<VkDebugUtilsLabelEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT);
  label.pLabelName = name.c_str();
  begin_label_(cmd, &label);
}

void GpuDevice::end_label(VkCommandBuffer cmd) const {
  if (end_label_) end_label_(cmd);
}

void GpuDevice::push_descriptors(VkCommandBuffer cmd, VkPipelineBindPoint bind_point, VkPipelineLayout layout,
                                 const std::vector<VkWriteDescriptorSet>& writes) const {
  push_descriptor_set_(cmd, bind_point, layout, 0, static_cast<uint32_t>(writes.size()), writes.data());
}

void GpuDevice::renderdoc_begin() {
  if (!renderdoc_) return;
  // RENDERDOC_DEVICEPOINTER_FROM_VKINSTANCE: the dispatch table pointer inside the handle.
  static_cast<RenderDocApi*>(renderdoc_)->StartFrameCapture(*reinterpret_cast<void**>(instance_), nullptr);
}

void GpuDevice::renderdoc_end() {
  if (!renderdoc_) return;
  static_cast<RenderDocApi*>(renderdoc_)->EndFrameCapture(*reinterpret_cast<void**>(instance_), nullptr);
}

}  // namespace nightcap
