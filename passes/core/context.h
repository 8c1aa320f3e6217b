// What a pass sees while it records: its declared resources, its parameters, pipelines built
// from its shaders, and helpers that keep Vulkan boilerplate out of the passes.
#pragma once

#include <vulkan/vulkan.h>

#include <cstring>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "passes/core/declared_pipeline.h"
#include "passes/core/device.h"
#include "passes/core/graph.h"
#include "passes/core/pipeline_cache.h"
#include "passes/core/sampler.h"

namespace nightcap {

class PassContext {
 public:
  struct Shared;  // executor state the context reaches into
  PassContext(Shared& shared, const CompiledPass& pass);

  const std::string& pass() const { return pass_.decl->name; }
  const PassDecl& declaration() const { return *pass_.decl; }
  // The pass's parameters by type, as compile_graph resolved them; reading one the pass did not
  // declare, or as another type, throws GraphError.
  double param_float(const std::string& name) const;
  int64_t param_int(const std::string& name) const;  // an int, or an enum's value
  bool flag(const std::string& name) const;
  // Whether input `resource` holds one value at every texel, as the graph knows before the frame
  // runs (a skipped or folded writer): a pass may then take a cheaper path to the same bits. A
  // replay does not know it, so replay --verify checks that path against the general one.
  bool uniform(const std::string& resource) const { return pass_.uniform_inputs.count(resource) > 0; }
  const ResourceDesc& desc(const std::string& resource) const;
  // Bytes of a resource known on the host (scene data, CPU pass outputs). Throws otherwise.
  std::span<const uint8_t> host(const std::string& resource) const;
  std::vector<std::string> inputs_with_prefix(const std::string& prefix) const;
  // Whether the pass reads `resource` here: false for an optional input the frame lacks (the
  // C++ side of a shader's `#ifdef NC_BINDING_<name>`).
  bool reads(const std::string& resource) const;

  // CPU passes fill their outputs here.
  std::vector<uint8_t>& output(const std::string& resource);
  // A CPU pass's output set to the bytes of `records` (none: empty).
  template <typename Record>
  void store(const std::string& resource, std::span<const Record> records) {
    static_assert(std::is_trivially_copyable_v<Record>);
    std::vector<uint8_t>& out = output(resource);
    out.resize(records.size_bytes());
    if (!records.empty()) std::memcpy(out.data(), records.data(), records.size_bytes());
  }

  // GPU passes.
  VkCommandBuffer cmd() const;
  GpuDevice& gpu() const;
  VkBuffer buffer(const std::string& resource) const;
  // A view of one mip (or every mip: -1) and one layer as a 2D image (or every layer: -1, as the
  // image's own type: array, cube or 3D).
  VkImageView view(const std::string& resource, ViewAspect aspect = ViewAspect::natural, int mip = -1, int layer = -1);
  // The pipeline the declaration describes (passes/core/declared_pipeline.h).
  // `specialization`: constant_id i of the pass's shaders takes value i (a variant of the pass).
  void bind_pipeline(const std::vector<int32_t>& specialization = {});
  void bind(const GraphicsPipelineDesc& desc);
  void bind(const ComputePipelineDesc& desc);
  // The first binding the declaration gives `resource` (a resource or a read prefix).
  uint32_t slot(const std::string& resource) const;
  void push(const std::vector<Binding>& bindings);
  // The bindings the declaration implies (declared_bindings); `level`: the mip level this
  // dispatch works on, for images declared with level_mips. A prefix read's textures are pushed
  // per draw (push_draw_textures).
  void push_declared(std::optional<uint32_t> level = std::nullopt);
  // The textures of the pass's prefix read (PassDecl::read_all) for the next draws, one per slot
  // it declares, each through its own sampler (a material's textures).
  struct DrawTexture {
    std::string resource;
    SamplerDesc sampler;
  };
  void push_draw_textures(std::span<const DrawTexture> textures);
  void push_constants(const void* data, uint32_t bytes);
  template <typename Constants>
  void push_constants(const Constants& constants) {
    static_assert(std::is_trivially_copyable_v<Constants>, "push constants are copied as bytes");
    push_constants(&constants, uint32_t(sizeof constants));
  }
  VkSampler sampler(const SamplerDesc& desc);
  VkSampler nearest_clamp();
  // Colour outputs and an optional depth output, at one mip and one layer of each: declared
  // fresh outputs are cleared to their clear value, modified ones keep their previous contents.
  // The pass must have declared that mip and layer as an attachment.
  void begin_rendering(const std::vector<std::string>& colors, const std::string& depth = "", uint32_t mip = 0,
                       uint32_t layer = 0);
  // The declared colour attachments in declaration order and the declared depth attachment.
  void begin_rendering();
  // Copies layer `from_layer` (mip 0) of `from`, an image the pass reads, into layer `to_layer`
  // of `to`, an image of the same format and size it writes, by transfer commands between the
  // states the graph planned for the pass: on a CPU driver a copy costs a small part of a
  // full-screen draw. Texel (x, y) of `to` takes texel (x + dx, y + dy) of `from`; those with none
  // inside it keep `to`'s clear value. begin_rendering then loads that layer of `to` rather than
  // clearing it. Called before the pass renders to or reads those layers.
  void copy_layer(const std::string& from, uint32_t from_layer, const std::string& to, uint32_t to_layer,
                  int32_t dx = 0, int32_t dy = 0);
  // Copies the whole of `from`, an image or buffer the pass reads, into `to`, one of the same
  // format, size, mips and layers (or bytes) it writes (every subresource), by transfer commands
  // between the states the graph planned for the pass: a history carried into this frame's version.
  void copy_resource(const std::string& from, const std::string& to);
  // Sets layers [first_layer, first_layer + count) (every mip) of `to`, an image the pass writes, to
  // `value` by a transfer clear between the states the graph planned for the pass, before the
  // pass writes them otherwise.
  void clear_layers(const std::string& to, uint32_t first_layer, uint32_t count, const VkClearValue& value);
  void end_rendering();
  // Orders this pass's own storage writes before its next reads (e.g. between mip levels),
  // indirect arguments it wrote included.
  void storage_barrier();
  // Draws and dispatches whose arguments a GPU pass computed: `resource` must be declared as
  // Use::indirect_args, so the graph's barrier makes the arguments visible to the indirect read,
  // or be a buffer this pass writes as storage, made visible by its own storage_barrier().
  void dispatch_indirect(const std::string& resource, uint64_t offset = 0);
  void draw_indexed_indirect(const std::string& resource, uint64_t offset, uint32_t count, uint32_t stride);

 private:
  DescOf declared_descs() const;         // desc() as the declared_* functions take it
  std::string binding_preamble() const;  // binding_defines of the declaration
  const BoundUse* find_use(const std::string& resource) const;
  double param_value(const std::string& name, std::initializer_list<ParamType> types) const;
  // The buffer holding `bytes` of indirect arguments at `offset`; throws unless declared so.
  VkBuffer indirect_args(const std::string& resource, uint64_t offset, uint64_t bytes) const;
  // Throws unless the pass declared a use of every subresource the view selects, in a use that
  // leaves it in `layout` (the graph's barriers put it there and nowhere else).
  void check_declared(const std::string& resource, int mip, int layer, VkImageLayout layout) const;
  Shared& shared_;
  const CompiledPass& pass_;
  std::set<std::pair<std::string, uint32_t>> copied_layers_;  // (resource, layer) filled by copy_layer
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipelineBindPoint bind_point_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  uint32_t push_constant_bytes_ = 0;
};

}  // namespace nightcap
