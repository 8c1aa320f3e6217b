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

std::string cull_name(VkCullModeFlags mode) {
  static const char* names[] = {"none", "front", "back", "front_and_back"};
  return mode < 4 ? names[mode] : "cull mode " + std::to_string(mode);
}

std::string name_of(VkBlendFactor factor) {
  static const char* names[] = {"zero",
                                "one",
                                "src_color",
                                "one_minus_src_color",
                                "dst_color",
                                "one_minus_dst_color",
                                "src_alpha",
                                "one_minus_src_alpha",
                                "dst_alpha",
                                "one_minus_dst_alpha",
                                "constant_color",
                                "one_minus_constant_color",
                                "constant_alpha",
                                "one_minus_constant_alpha",
                                "src_alpha_saturate"};
  return factor >= 0 && factor < 15 ? names[factor] : "blend factor " + std::to_string(factor);
}

std::string name_of(VkBlendOp op) {
  static const char* names[] = {"add", "subtract", "reverse_subtract", "min", "max"};
  return op >= 0 && op < 5 ? names[op] : "blend op " + std::to_string(op);
}

nlohmann::json describe(const BlendState& b) {
  std::string mask;
  for (int c = 0; c < 4; ++c)
    if (b.write_mask & (1u << c)) mask += "rgba"[c];
  if (!b.enabled) return {{"enabled", false}, {"write_mask", mask}};
  return {{"enabled", true},
          {"color", {{"src", name_of(b.src_color)}, {"dst", name_of(b.dst_color)}, {"op", name_of(b.color_op)}}},
          {"alpha", {{"src", name_of(b.src_alpha)}, {"dst", name_of(b.dst_alpha)}, {"op", name_of(b.alpha_op)}}},
          {"write_mask", mask}};
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
  nlohmann::json colors = nlohmann::json::array(), blends = nlohmann::json::array();
  for (size_t i = 0; i < desc.color_formats.size(); ++i) {
    colors.push_back(name_of(desc.color_formats[i]));
    blends.push_back(describe(i < desc.blend.size() ? desc.blend[i] : BlendState{}));
  }
  const RasterState& r = desc.raster;
  nlohmann::json dynamic = {"viewport", "scissor", "stencil_reference"};
  if (r.per_draw_faces) dynamic.insert(dynamic.end(), {"cull_mode", "front_face"});
  nlohmann::json j = {
      {"kind", "graphics"},
      {"vertex", desc.vertex},
      {"fragment", desc.fragment},
      {"bindings", bindings_json(desc.bindings)},
      {"push_constant_bytes", desc.push_constant_bytes},
      {"color_formats", colors},
      {"blend", blends},
      {"raster",
       {{"cull_mode", cull_name(r.cull_mode)},
        {"front_face", r.front_face == VK_FRONT_FACE_CLOCKWISE ? "clockwise" : "counter_clockwise"},
        // Per draw: not culled where the material is double-sided, winding flipped where mirrored.
        {"per_draw_faces", r.per_draw_faces},
        {"depth_bias",
         {{"constant", r.depth_bias.constant}, {"slope", r.depth_bias.slope}, {"clamp", r.depth_bias.clamp}}}}},
      {"specialization", desc.specialization},
      {"dynamic_state", dynamic}};
  if (desc.depth_format != VK_FORMAT_UNDEFINED) {
    const DepthStencilState& d = desc.depth_stencil;
    j["depth"] = {
        {"format", name_of(desc.depth_format)}, {"test", d.test}, {"write", d.write}, {"compare", name_of(d.compare)}};
    j["stencil"] = {{"test", d.stencil_test()},
                    {"compare", name_of(d.stencil_compare)},
                    {"write", d.stencil_write},
                    {"read_mask", d.stencil_read_mask},
                    {"write_mask", d.stencil_write_mask}};
  }
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
  // The description names every piece of state the pipeline is built from, so it is the key.
  std::ostringstream key;
  key << "g:" << code_key(vs) << ":" << (fs.empty() ? "-" : code_key(fs)) << ":" << describe(desc).dump();
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
  raster.cullMode = desc.raster.cull_mode;
  raster.frontFace = desc.raster.front_face;
  raster.depthBiasEnable = desc.raster.depth_bias.enabled();
  raster.depthBiasConstantFactor = desc.raster.depth_bias.constant;
  raster.depthBiasSlopeFactor = desc.raster.depth_bias.slope;
  raster.depthBiasClamp = desc.raster.depth_bias.clamp;
  raster.lineWidth = 1.0f;
  auto multisample =
      vk_struct<VkPipelineMultisampleStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  auto depth =
      vk_struct<VkPipelineDepthStencilStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  const DepthStencilState& ds = desc.depth_stencil;
  depth.depthTestEnable = ds.test;
  depth.depthWriteEnable = ds.write;
  depth.depthCompareOp = ds.compare;
  if (ds.stencil_test()) {
    depth.stencilTestEnable = VK_TRUE;
    depth.front = {VK_STENCIL_OP_KEEP,
                   ds.stencil_write ? VK_STENCIL_OP_REPLACE : VK_STENCIL_OP_KEEP,
                   VK_STENCIL_OP_KEEP,
                   ds.stencil_compare,
                   ds.stencil_read_mask,
                   ds.stencil_write_mask,
                   0};
    depth.back = depth.front;
  }
  std::vector<VkPipelineColorBlendAttachmentState> blends(desc.color_formats.size());
  for (size_t i = 0; i < blends.size(); ++i) {
    const BlendState b = i < desc.blend.size() ? desc.blend[i] : BlendState{};
    blends[i] = {b.enabled, b.src_color, b.dst_color, b.color_op, b.src_alpha, b.dst_alpha, b.alpha_op, b.write_mask};
  }
  auto blend = vk_struct<VkPipelineColorBlendStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  blend.attachmentCount = static_cast<uint32_t>(blends.size());
  blend.pAttachments = blends.data();
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR,
                                           VK_DYNAMIC_STATE_STENCIL_REFERENCE, VK_DYNAMIC_STATE_CULL_MODE,
                                           VK_DYNAMIC_STATE_FRONT_FACE};
  auto dynamic = vk_struct<VkPipelineDynamicStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = desc.raster.per_draw_faces ? 5 : 3;
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
