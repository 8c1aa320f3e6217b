// How a pass declares itself to the render graph: name, inputs, outputs (with formats and sizes
// relative to the output), parameters, required scene features, shaders, and the function that
// records (or, for CPU passes, computes) its work. The graph owns ordering, culling, barriers,
// allocation, timing and capture; a pass only says what it reads and writes.
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "passes/core/buffer_schema.h"
#include "passes/core/contract.h"
#include "passes/core/format.h"
#include "passes/core/history_name.h"
#include "passes/core/params.h"
#include "passes/core/pipeline_state.h"
#include "passes/core/resource_kind.h"
#include "passes/core/sampler.h"

namespace nightcap {

class PassContext;

enum class PassType { graphics, compute, cpu };

// How a pass touches a resource; barriers and image layouts derive from it.
enum class Use {
  sampled,        // read through a sampler or texelFetch
  storage_read,   // storage image or buffer, read
  storage_write,  // storage image or buffer, written (read-write allowed)
  color_attachment,
  depth_attachment,  // depth-stencil attachment, read and written
  uniform_buffer,
  index_buffer,
  indirect_args,  // draw or dispatch arguments of vkCmd*Indirect (PassContext::dispatch_indirect)
  host,           // CPU pass: read or written on the host
};

// The aspect of an image a view shows: natural is the depth of a depth format, else the colour.
enum class ViewAspect { natural, depth, stencil };

// Resources each holding one value at every texel (or, for a buffer, a zero fill), by name.
using UniformValues = std::map<std::string, VkClearValue>;
// Whether two values of an image of `format` are the same bits (a depth format compares depth and stencil).
bool same_value(VkFormat format, const VkClearValue& a, const VkClearValue& b);

struct SizeRule {
  enum class Mode { output, output_half, output_tiles, absolute, like, square_param, params } mode = Mode::output;
  uint32_t width = 0, height = 0;  // absolute
  std::string like;                // like: same size as this resource
  std::string param{};             // square_param: a square whose side is this parameter of the writing pass
  uint32_t tile = 1;               // output_tiles: a texel per tile of tile×tile output pixels, rounded up
  std::string tile_param{};        // output_tiles: when named, the writing pass's parameter gives `tile`
  std::string height_param{};      // params: the writing pass's parameters `param` and this give width and height
};

struct ImageDecl {
  ImageDecl() = default;
  ImageDecl(VkFormat image_format, ResourceKind image_kind) : format(image_format), kind(image_kind) {}
  VkFormat format = VK_FORMAT_UNDEFINED;
  ResourceKind kind = kinds::colour;
  SizeRule size;
  uint32_t mips = 1;        // at most this many (a small image has fewer); 0: the whole chain down to 1x1
  uint32_t layers = 1;      // more than 1: a 2D array
  uint32_t depth = 1;       // more than 1: a 3D image of that many slices (one layer)
  std::string depth_param;  // when named, the writing pass's parameter times `depth` gives the slices
  bool cube = false;        // layers are cube faces (a multiple of 6, square): sampled as a cube
  VkClearValue clear{};     // contents when the writer is skipped, and the attachment clear
};

// The part of an image a use touches: a range of mips and a range of layers (3D slices are not
// separate: a 3D image has one layer). kAll: from base to the last one. Buffers are whole.
struct Subresources {
  static constexpr uint32_t kAll = ~0u;
  uint32_t base_mip = 0, mip_count = kAll;
  uint32_t base_layer = 0, layer_count = kAll;

  static Subresources mip(uint32_t m) { return {m, 1, 0, kAll}; }
  static Subresources layer(uint32_t l) { return {0, kAll, l, 1}; }
  static Subresources at(uint32_t m, uint32_t l) { return {m, 1, l, 1}; }
  bool contains(uint32_t m, uint32_t l) const {
    return m >= base_mip && m - base_mip < mip_count && l >= base_layer && l - base_layer < layer_count;
  }
  bool operator==(const Subresources&) const = default;
};

struct BufferDecl {
  BufferDecl() = default;
  explicit BufferDecl(ResourceKind buffer_kind, uint64_t bytes = 0) : kind(buffer_kind), size(bytes) {}
  ResourceKind kind = kinds::buffer;
  uint64_t size = 0;                   // 0: the producing CPU pass decides at run time (a GPU writer must declare it)
  std::optional<BufferSchema> schema;  // how its bytes decode (PassDecl::layout); none: 32-bit words
};

// A concrete resource: what the graph allocates and the capture records.
struct ResourceDesc {
  bool is_buffer = false;
  ResourceKind kind = kinds::colour;
  VkFormat format = VK_FORMAT_UNDEFINED;
  ImageExtent extent;
  uint64_t buffer_size = 0;
  VkClearValue clear{};
  bool cube = false;  // layers are cube faces

  uint64_t raw_bytes() const;
};

struct ResourceUse {
  std::string resource;
  Use use = Use::sampled;
  Subresources range;     // images: the mips and layers the use touches (all by default)
  bool prefix = false;    // reads every resource whose name starts with `resource`
  bool modifies = false;  // output that starts from the resource's previous version
  bool history = false;   // input: the value `resource` had at the end of the previous frame
  bool optional = false;  // input: read only where something produces it (PassDecl::read_optional)
  bool is_buffer = false;
  ImageDecl image;
  BufferDecl buffer;
  ComparisonContract contract;  // outputs: how two versions of it compare (exact by default)
  // The name the pass binds it by: previous(resource) for a history input.
  std::string bound_name() const { return history ? previous(resource) : resource; }
  // The name its shaders give its binding, NC_BINDING(name) (PassDecl::as; declared_pipeline.h).
  std::string shader_name() const;
  std::string role;  // PassDecl::as
  // Consecutive descriptor bindings it takes (PassDecl::slots) if a shader binds it.
  uint32_t slots = 1;
  // A sampled image's sampler (PassDecl::sampler); none: nearest, clamped to the edge.
  std::optional<SamplerDesc> sampler;
  // The aspect each of its bindings shows (PassDecl::aspects); empty: one natural binding.
  std::vector<ViewAspect> aspects;
  // Bound once per entry at mip `level + entry` of the level a dispatch works on
  // (PassDecl::level_mips); empty: bound as its range declares.
  std::vector<int> level_mips;
};

// What a skip condition may look at: the scene's features and the frame.
struct SkipContext {
  std::set<std::string> features;
  uint32_t frame_index = 0;
  bool camera_moved = false;
  uint32_t width = 0, height = 0;  // the output size (compile_graph sets it from GraphSettings)
  bool camera_cut = false;         // the view jumped: every history starts again from its initial value
};

struct PassDecl {
  std::string name;
  PassType type = PassType::graphics;
  // The part of the frame it belongs to ("shadows", "probes", "geometry", "lighting", "post"), set by the
  // frame's assembly: the report's overview groups passes by it. Empty outside a frame.
  std::string stage;
  std::vector<ResourceUse> inputs, outputs;
  std::vector<ParamDecl> params;
  std::vector<std::string> features;  // all must be present, or the pass is skipped
  std::vector<std::string> shaders;   // GLSL paths relative to passes/
  // Pipeline state: one pipeline per pass, built from the declaration (passes/core/declared_pipeline.h).
  RasterState raster_state;
  DepthStencilState depth_stencil_state;
  std::map<std::string, BlendState> blend_states;  // by colour output; absent: no blending
  uint32_t push_constant_bytes = 0;
  std::function<void(PassContext&)> execute;
  // Extra frame-dependent skip condition: returns the reason, or "" to run.
  std::function<std::string(const SkipContext&)> skip_if;
  // Set by skip_when_cleared: sets of inputs whose being cleared makes the pass's work known.
  struct ClearedSkip {
    std::vector<std::string> inputs;
    std::function<bool(const ParamValues&)> exact;  // absent: for every parameter
    std::string reason() const;                     // "inputs all cleared (a, b)"
  };
  std::vector<ClearedSkip> cleared_skips;
  // Set by fold_when_uniform.
  struct UniformFold {
    std::vector<std::string> inputs;
    std::function<std::optional<UniformValues>(const UniformValues& inputs, const ParamValues&)> outputs;
    std::string reason() const;  // "inputs uniform (a, b): folded"
  };
  std::vector<UniformFold> uniform_folds;
  // Set by warn_from: outputs the renderer reads back after the frame, and what each says.
  struct OutputWarning {
    std::string output;
    std::function<std::string(std::span<const uint8_t>)> check;  // the warning, or "" when all is well
  };
  std::vector<OutputWarning> warnings;
  std::string disabled_reason;  // set by can_disable: the skip reason when `enabled` is 0

  PassDecl(std::string pass_name, PassType pass_type) : name(std::move(pass_name)), type(pass_type) {}
  PassDecl& read(std::string resource, Use use);
  PassDecl& read_all(std::string prefix, Use use);
  PassDecl& write(std::string resource, Use use, ImageDecl decl);
  PassDecl& write(std::string resource, Use use, BufferDecl decl);
  PassDecl& modify(std::string resource, Use use);
  // The same, restricted to some mips and/or layers of an image (e.g. read mip i - 1 while
  // writing mip i, or render into one layer of an array). A fresh write of part of an image
  // leaves the rest at the declared clear value.
  PassDecl& read(std::string resource, Use use, Subresources range);
  PassDecl& write(std::string resource, Use use, ImageDecl decl, Subresources range);
  PassDecl& modify(std::string resource, Use use, Subresources range);
  // The value `resource` had at the end of the previous frame, bound as previous(resource). On
  // frame 0, after a camera cut or a resize it is the resource's declared clear value. The
  // resource's writer runs whenever this pass does, so the next frame has its history.
  PassDecl& read_previous(std::string resource, Use use);
  // An input the pass reads when the frame has it, when a pass writes it or it is imported
  // (compile_graph). Where nothing does, the pass runs without it: no dependency, no binding,
  // and its shaders' NC_BINDING_<name> is undefined, so they `#ifdef` the code that reads it.
  // The frame connects a new producer (AO, fog) without an edit to its readers.
  PassDecl& read_optional(std::string resource, Use use);
  // The name the shaders give the use just declared, in place of its resource's: a shader that
  // several passes share binds "draws", not "draws.depth.prepass"; bloom's levels read their
  // "source". A GLSL identifier.
  PassDecl& as(std::string role);
  // A bool parameter `enabled` (default true): false skips the pass with `reason`, e.g. "fixed
  // exposure". Passes that carry out one pass of frame.md in steps share one switch, a parameter
  // of `group` (bloom.level0…5: `--set bloom.enabled=0`).
  PassDecl& can_disable(std::string reason, std::string group = "");
  // Parameters (passes/core/params.h), read by PassContext::param_float, param_int and flag.
  PassDecl& param(ParamDecl decl);
  PassDecl& param_float(std::string param_name, double default_value, double min, double max, std::string help);
  PassDecl& param_int(std::string param_name, double default_value, double min, double max, std::string help);
  PassDecl& flag(std::string param_name, bool default_value, std::string help);
  PassDecl& choice(std::string param_name, double default_value, std::vector<ParamChoice> choices, std::string help);
  PassDecl& needs(std::string feature);
  PassDecl& shader(std::string path);
  // Descriptor set 0 binds the inputs, then the outputs, in declaration order, one binding
  // each for uniform and storage buffers, sampled and storage images; `slots` gives `resource`
  // (a resource or a read prefix) `count` consecutive bindings: the textures of a prefix read
  // bound per draw, one image bound at two mips.
  PassDecl& slots(const std::string& resource, uint32_t count);
  // The sampler sampled input `resource` is bound through (PassContext::push_declared), where
  // nearest clamp-to-edge does not suit its shader.
  PassDecl& sampler(const std::string& resource, SamplerDesc desc);
  // Sampled depth-stencil input `resource` bound once per aspect, in consecutive bindings
  // (e.g. depth then stencil, or stencil alone).
  PassDecl& aspects(const std::string& resource, std::vector<ViewAspect> per_binding);
  // Image `resource`, worked on a mip level per dispatch, bound once per offset in consecutive
  // bindings, each at mip `level + offset` (at least 0) of the level that
  // PassContext::push_declared(level) names: {-1, 0} reads the level above the one it writes.
  PassDecl& level_mips(const std::string& resource, std::vector<int> offsets);
  PassDecl& raster(RasterState state);
  PassDecl& depth_stencil(DepthStencilState state);
  PassDecl& blend(const std::string& output, BlendState state);
  // The push constants are a Constants struct (its size is the pipeline's push-constant range).
  template <typename Constants>
  PassDecl& push_constants();
  PassDecl& run(std::function<void(PassContext&)> function);
  PassDecl& skip_when(std::function<std::string(const SkipContext&)> condition);
  // Skipped when every one of `inputs` holds its declared clear value because the pass that
  // writes it was skipped (a scene with nothing to draw clears the G-buffer, and so on down the
  // frame), or is a list a CPU pass left empty this frame (no moving instance in view): the
  // pass would then compute its outputs' declared clear values, or leave the outputs it
  // modifies as they were, whatever its other inputs (constants, tables) hold, and the graph
  // clears them instead of running it. `exact` says for which parameters that is true (absent:
  // all). Each call adds one such set; any of them skips the pass. An empty list is known only
  // once its CPU pass has run (the executor still issues the barriers planned around the pass),
  // so a pass it skips either only modifies its outputs — the capture records its inputs and a
  // replay checks the claim by running it — or writes fresh outputs that only passes skipping on
  // some of the same lists read: they are left cleared, read by no pass that runs, and the
  // capture records no inputs for it.
  PassDecl& skip_when_cleared(std::vector<std::string> inputs, std::function<bool(const ParamValues&)> exact = {});
  // The first of cleared_skips whose inputs are all in `cleared` and that is exact for `params`.
  const ClearedSkip* cleared_skip(const std::set<std::string>& cleared, const ParamValues& params) const;
  // Folded when every one of `inputs` is uniform (one value at every texel of every mip and
  // layer) and the graph knows that value before the frame runs: it was a skipped pass's clear
  // value or another fold's result. `outputs` then returns the value the pass would write at
  // every texel of each output, bit for bit as the output stores it, or nothing where it cannot
  // tell; instead of running the pass, the graph clears the part of each output it writes to
  // that value (the rest of a fresh output to its declared clear value), and leaves a modified
  // output as it is where it already holds the value. Decided by compile_graph alone. The
  // capture records the inputs, so a replay checks the fold by running the pass.
  PassDecl& fold_when_uniform(std::vector<std::string> inputs, decltype(UniformFold::outputs) outputs);
  // How `output` compares across replays, builds and devices (passes/core/contract.h).
  PassDecl& compare(const std::string& output, ComparisonContract contract);
  // How the bytes of buffer `output` decode (passes/core/buffer_schema.h).
  PassDecl& layout(const std::string& output, BufferSchema schema);
  // A condition only the GPU's result shows (a list that overflowed): after each frame the
  // renderer reads `output` back and prints what `check` returns on stderr unless it is empty.
  PassDecl& warn_from(const std::string& output, std::function<std::string(std::span<const uint8_t>)> check);
  // A fragment shader drawn over the whole output, recorded from the declaration alone
  // (passes/core/fullscreen.cpp): set 0 binds the GPU inputs as PassContext::push_declared
  // does (images through a nearest clamp-to-edge sampler unless declared otherwise, depth by
  // its depth aspect), the colour outputs are
  // the render targets in declaration order, and `make_constants(ctx)` — a struct built from
  // the parameters — fills the push constants.
  PassDecl& fullscreen(std::string fragment);
  template <typename MakeConstants>
  PassDecl& fullscreen(std::string fragment, MakeConstants make_constants);

  ParamValues default_params() const;  // resolve_params with no overrides
  const ParamDecl* find_param(const std::string& param_name) const;
  const ComparisonContract& contract_of(const std::string& output) const;
  const BufferSchema* schema_of(const std::string& output) const;

 private:
  bool last_use_is_output_ = false;  // which list as() names the last use of
};

const PassDecl* find_pass(const std::vector<PassDecl>& passes, const std::string& name);

// Records a full-screen pass from its declaration; `constants` are the push constants' bytes,
// `specialization` the shaders' specialization constants (PassContext::bind_pipeline).
void record_fullscreen(PassContext& ctx, std::span<const uint8_t> constants,
                       const std::vector<int32_t>& specialization = {});

template <typename Constants>
PassDecl& PassDecl::push_constants() {
  static_assert(std::is_trivially_copyable_v<Constants>, "push constants are copied as bytes");
  push_constant_bytes = uint32_t(sizeof(Constants));
  return *this;
}

template <typename MakeConstants>
PassDecl& PassDecl::fullscreen(std::string fragment, MakeConstants make_constants) {
  fullscreen(fragment);
  push_constants<std::invoke_result_t<MakeConstants, const PassContext&>>();
  execute = [make_constants](PassContext& ctx) {
    const auto constants = make_constants(static_cast<const PassContext&>(ctx));
    record_fullscreen(ctx, {reinterpret_cast<const uint8_t*>(&constants), sizeof constants});
  };
  return *this;
}

}  // namespace nightcap
