#include <xxhash.h>

#include <sstream>

#include "passes/core/format.h"
#include "passes/core/pipeline_cache.h"

namespace nightcap {
namespace {

std::string code_key(const std::vector<uint32_t>& code) {
  return std::to_string(XXH3_64bits(code.data(), code.size() * 4));
}

struct Specialization {
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo info{};
  explicit Specialization(const std::vector<int32_t>& values) {
    for (uint32_t i = 0; i < values.size(); ++i) entries.push_back({i, i * 4, 4});
    info.mapEntryCount = static_cast<uint32_t>(entries.size());
    info.pMapEntries = entries.data();
    info.dataSize = values.size() * 4;
    info.pData = values.data();
  }
};

std::string name_of(VkDescriptorType type) {
  switch (type) {
    case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
      return "uniform_buffer";
    case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
      return "storage_buffer";
    case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
      return "combined_image_sampler";
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
      return "storage_image";
    default:
      return "descriptor type " + std::to_string(type);
  }
}

std::string name_of(VkCompareOp op) {
  static const char* names[] = {"never", "less", "equal", "less_or_equal", "greater", "not_equal", "greater_or_equal",
                                "always"};
  return op >= 0 && op < 8 ? names[op] : "compare op " + std::to_string(op);
}

std::string name_of(VkFormat format) {
  const auto info = format_info(format);
  return info ? std::string(info->name) : "format " + std::to_string(format);
}

nlohmann::json bindings_json(const std::vector<VkDescriptorType>& bindings) {
  nlohmann::json list = nlohmann::json::array();
  for (VkDescriptorType type : bindings) list.push_back(name_of(type));
  return list;
}

// Pipelines are named by their shader paths, not by the pass that first asked for one: the cache
// hands the same pipeline to every pass with the same shaders and state, on every frame, so the
// paths are the only name true for all of them. Constants that specialise the code are part of
// it ("deferred.frag {1,0}").
std::string pipeline_name(const std::string& shaders, const std::vector<int32_t>& specialization) {
  if (specialization.empty()) return shaders;
  std::string name = shaders + " {";
  for (size_t i = 0; i < specialization.size(); ++i) name += (i ? "," : "") + std::to_string(specialization[i]);
  return name + "}";
}

std::string filter_name(VkFilter filter) { return filter == VK_FILTER_NEAREST ? "nearest" : "linear"; }

std::string wrap_name(VkSamplerAddressMode mode) {
  switch (mode) {
    case VK_SAMPLER_ADDRESS_MODE_REPEAT:
      return "repeat";
    case VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT:
      return "mirrored_repeat";
    case VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE:
      return "clamp_to_edge";
    default:
      return "address mode " + std::to_string(mode);
  }
}

}  // namespace

nlohmann::json describe(const GraphicsPipelineDesc& desc) {
  nlohmann::json colors = nlohmann::json::array();
  for (VkFormat f : desc.color_formats) colors.push_back(name_of(f));
  nlohmann::json j = {{"kind", "graphics"},
                      {"vertex", desc.vertex},
                      {"fragment", desc.fragment},
                      {"bindings", bindings_json(desc.bindings)},
                      {"push_constant_bytes", desc.push_constant_bytes},
                      {"color_formats", colors},
                      {"specialization", desc.specialization},
                      {"stencil_write", desc.stencil_write},
                      // Cull mode and front face are dynamic: nightcap sets them per draw.
                      {"dynamic_state", {"viewport", "scissor", "cull_mode", "front_face", "stencil_reference"}}};
  if (desc.depth_format != VK_FORMAT_UNDEFINED)
    j["depth"] = {{"format", name_of(desc.depth_format)},
                  {"test", desc.depth_test},
                  {"write", desc.depth_write},
                  {"compare", name_of(desc.depth_compare)}};
  return j;
}

nlohmann::json describe(const ComputePipelineDesc& desc) {
  return {{"kind", "compute"},
          {"shader", desc.shader},
          {"bindings", bindings_json(desc.bindings)},
          {"push_constant_bytes", desc.push_constant_bytes},
          {"specialization", desc.specialization}};
}

nlohmann::json describe(const SamplerDesc& desc) {
  return {{"mag_filter", filter_name(desc.mag_filter)},
          {"min_filter", filter_name(desc.min_filter)},
          {"mipmap_mode", desc.mipmap_mode == VK_SAMPLER_MIPMAP_MODE_NEAREST ? "nearest" : "linear"},
          {"mipmaps", desc.mipmaps},
          {"wrap_u", wrap_name(desc.wrap_u)},
          {"wrap_v", wrap_name(desc.wrap_v)}};
}

PipelineCache::~PipelineCache() {
  VkDevice device = gpu_.device();
  for (auto& [key, entry] : pipelines_) {
    vkDestroyPipeline(device, entry.pipeline, nullptr);
    vkDestroyPipelineLayout(device, entry.layout, nullptr);
    vkDestroyDescriptorSetLayout(device, entry.set_layout, nullptr);
  }
  for (auto& [key, sampler] : samplers_) vkDestroySampler(device, sampler, nullptr);
  for (VkShaderModule m : modules_) vkDestroyShaderModule(device, m, nullptr);
}

VkShaderModule PipelineCache::module(const std::vector<uint32_t>& code, const std::string& path) {
  auto info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  info.codeSize = code.size() * 4;
  info.pCode = code.data();
  VkShaderModule m;
  vk_check(vkCreateShaderModule(gpu_.device(), &info, nullptr, &m), "vkCreateShaderModule");
  gpu_.name(VK_OBJECT_TYPE_SHADER_MODULE, m, path);
  modules_.push_back(m);
  return m;
}

std::pair<VkDescriptorSetLayout, VkPipelineLayout> PipelineCache::layout(const std::vector<VkDescriptorType>& bindings,
                                                                         uint32_t push_bytes,
                                                                         const std::string& pipeline) {
  std::vector<VkDescriptorSetLayoutBinding> list;
  for (uint32_t i = 0; i < bindings.size(); ++i) list.push_back({i, bindings[i], 1, VK_SHADER_STAGE_ALL, nullptr});
  auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set_info.bindingCount = static_cast<uint32_t>(list.size());
  set_info.pBindings = list.data();
  VkDescriptorSetLayout set_layout;
  vk_check(vkCreateDescriptorSetLayout(gpu_.device(), &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  gpu_.name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, set_layout, pipeline + " set layout");
  VkPushConstantRange range{VK_SHADER_STAGE_ALL, 0, push_bytes};
  auto info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  info.setLayoutCount = 1;
  info.pSetLayouts = &set_layout;
  info.pushConstantRangeCount = push_bytes ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout pipeline_layout;
  vk_check(vkCreatePipelineLayout(gpu_.device(), &info, nullptr, &pipeline_layout), "vkCreatePipelineLayout");
  gpu_.name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, pipeline_layout, pipeline + " layout");
  return {set_layout, pipeline_layout};
}

const PipelineCache::Entry& PipelineCache::graphics(const GraphicsPipelineDesc& desc, const std::vector<uint32_t>& vs,
                                                    const std::vector<uint32_t>& fs) {
  std::ostringstream key;
  key << "g:" << code_key(vs) << ":" << (fs.empty() ? "-" : code_key(fs)) << ":" << desc.push_constant_bytes << ":"
      << desc.depth_format << desc.depth_test << desc.depth_write << desc.depth_compare << desc.stencil_write;
  for (auto b : desc.bindings) key << "," << b;
  for (auto f : desc.color_formats) key << ";" << f;
  for (auto s : desc.specialization) key << "s" << s;
  auto it = pipelines_.find(key.str());
  if (it != pipelines_.end()) return it->second;

  const std::string name =
      pipeline_name(desc.fragment.empty() ? desc.vertex : desc.vertex + " + " + desc.fragment, desc.specialization);
  Entry entry;
  std::tie(entry.set_layout, entry.layout) = layout(desc.bindings, desc.push_constant_bytes, name);
  Specialization spec(desc.specialization);
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  auto stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  stage.stage = VK_SHADER_STAGE_VERTEX_BIT;
  stage.module = module(vs, desc.vertex);
  stage.pName = "main";
  stage.pSpecializationInfo = &spec.info;
  stages.push_back(stage);
  if (!fs.empty()) {
    stage.stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stage.module = module(fs, desc.fragment);
    stages.push_back(stage);
  }
  auto vertex_input =
      vk_struct<VkPipelineVertexInputStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  auto assembly =
      vk_struct<VkPipelineInputAssemblyStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  auto viewport = vk_struct<VkPipelineViewportStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  auto raster =
      vk_struct<VkPipelineRasterizationStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  auto multisample =
      vk_struct<VkPipelineMultisampleStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  auto depth =
      vk_struct<VkPipelineDepthStencilStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  depth.depthTestEnable = desc.depth_test;
  depth.depthWriteEnable = desc.depth_write;
  depth.depthCompareOp = desc.depth_compare;
  if (desc.stencil_write) {
    depth.stencilTestEnable = VK_TRUE;
    depth.front = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_REPLACE, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    depth.back = depth.front;
  }
  std::vector<VkPipelineColorBlendAttachmentState> blends(desc.color_formats.size());
  for (auto& b : blends) b.colorWriteMask = 0xf;
  auto blend = vk_struct<VkPipelineColorBlendStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  blend.attachmentCount = static_cast<uint32_t>(blends.size());
  blend.pAttachments = blends.data();
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR,
                                           VK_DYNAMIC_STATE_CULL_MODE, VK_DYNAMIC_STATE_FRONT_FACE,
                                           VK_DYNAMIC_STATE_STENCIL_REFERENCE};
  auto dynamic = vk_struct<VkPipelineDynamicStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = 5;
  dynamic.pDynamicStates = dynamic_states;
  const bool has_stencil = desc.depth_format == VK_FORMAT_D32_SFLOAT_S8_UINT;
  auto rendering = vk_struct<VkPipelineRenderingCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO);
  rendering.colorAttachmentCount = static_cast<uint32_t>(desc.color_formats.size());
  rendering.pColorAttachmentFormats = desc.color_formats.data();
  rendering.depthAttachmentFormat = desc.depth_format;
  rendering.stencilAttachmentFormat = has_stencil ? desc.depth_format : VK_FORMAT_UNDEFINED;

  auto info = vk_struct<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
  info.pNext = &rendering;
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = entry.layout;
  vk_check(vkCreateGraphicsPipelines(gpu_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &entry.pipeline),
           "vkCreateGraphicsPipelines");
  gpu_.name(VK_OBJECT_TYPE_PIPELINE, entry.pipeline, name);
  return pipelines_.emplace(key.str(), entry).first->second;
}

const PipelineCache::Entry& PipelineCache::compute(const ComputePipelineDesc& desc, const std::vector<uint32_t>& cs) {
  std::ostringstream key;
  key << "c:" << code_key(cs) << ":" << desc.push_constant_bytes;
  for (auto b : desc.bindings) key << "," << b;
  for (auto s : desc.specialization) key << "s" << s;
  auto it = pipelines_.find(key.str());
  if (it != pipelines_.end()) return it->second;
  const std::string name = pipeline_name(desc.shader, desc.specialization);
  Entry entry;
  std::tie(entry.set_layout, entry.layout) = layout(desc.bindings, desc.push_constant_bytes, name);
  Specialization spec(desc.specialization);
  auto info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module(cs, desc.shader);
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = &spec.info;
  info.layout = entry.layout;
  vk_check(vkCreateComputePipelines(gpu_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &entry.pipeline),
           "vkCreateComputePipelines");
  gpu_.name(VK_OBJECT_TYPE_PIPELINE, entry.pipeline, name);
  return pipelines_.emplace(key.str(), entry).first->second;
}

VkSampler PipelineCache::sampler(const SamplerDesc& desc) {
  std::ostringstream key;
  key << desc.mag_filter << desc.min_filter << desc.mipmap_mode << desc.mipmaps << desc.wrap_u << desc.wrap_v;
  auto it = samplers_.find(key.str());
  if (it != samplers_.end()) return it->second;
  auto info = vk_struct<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  info.magFilter = desc.mag_filter;
  info.minFilter = desc.min_filter;
  info.mipmapMode = desc.mipmap_mode;
  info.addressModeU = desc.wrap_u;
  info.addressModeV = desc.wrap_v;
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  // glTF's NEAREST/LINEAR minification samples the base level only.
  info.maxLod = desc.mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
  VkSampler sampler;
  vk_check(vkCreateSampler(gpu_.device(), &info, nullptr, &sampler), "vkCreateSampler");
  // By state, e.g. "sampler linear/linear mip linear repeat/clamp": it is shared by every pass
  // and texture that samples this way.
  gpu_.name(VK_OBJECT_TYPE_SAMPLER, sampler,
            "sampler " + filter_name(desc.mag_filter) + "/" + filter_name(desc.min_filter) + " mip " +
                (desc.mipmaps ? (desc.mipmap_mode == VK_SAMPLER_MIPMAP_MODE_NEAREST ? "nearest" : "linear") : "none") +
                " " + wrap_name(desc.wrap_u) + "/" + wrap_name(desc.wrap_v));
  samplers_[key.str()] = sampler;
  return sampler;
}

}  // namespace nightcap
