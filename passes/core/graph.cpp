#include "passes/core/graph.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <map>
#include <set>

#include "passes/core/dependencies.h"

namespace nightcap {
namespace {

// A size a pass's parameter gives (SizeRule::tile_param, square_param and params, ImageDecl::depth_param):
// the parameter is declared an int from 1, or an enum of such values, so its checked value is one.
uint32_t size_from_param(const PassDecl& pass, const ParamValues& params, const std::string& param,
                         const std::string& what) {
  const ParamDecl* decl = pass.find_param(param);
  if (!decl) throw GraphError(what + " is sized by '" + param + "', which the pass does not declare");
  auto is_size = [](double value) { return value >= 1 && value <= double(std::numeric_limits<uint32_t>::max()); };
  const bool sizes =
      decl->type == ParamType::integer
          ? is_size(decl->min) && is_size(decl->max)
          : decl->type == ParamType::choice && std::all_of(decl->choices.begin(), decl->choices.end(),
                                                           [&](const ParamChoice& c) { return is_size(c.value); });
  if (!sizes)
    throw GraphError(what + " is sized by '" + param + "', which is not an int from 1 (or an enum of such values)");
  return uint32_t(params.at(param));
}

ResourceDesc resolve(const ResourceUse& out, const GraphSettings& settings,
                     const std::map<std::string, ResourceDesc>& known, const PassDecl& decl,
                     const ParamValues& params) {
  const std::string& pass = decl.name;
  ResourceDesc desc;
  if (out.is_buffer) {
    desc.is_buffer = true;
    desc.kind = out.buffer.kind;
    desc.buffer_size = out.buffer.size;
    return desc;
  }
  const ImageDecl& d = out.image;
  if (!format_info(d.format))
    throw GraphError(pass + ": output '" + out.resource + "' has a format nightcap does not record");
  desc.kind = d.kind;
  desc.format = d.format;
  desc.clear = d.clear;
  switch (d.size.mode) {
    case SizeRule::Mode::output:
      desc.extent.width = settings.width;
      desc.extent.height = settings.height;
      break;
    case SizeRule::Mode::output_half:
      desc.extent.width = (settings.width + 1) / 2;
      desc.extent.height = (settings.height + 1) / 2;
      break;
    case SizeRule::Mode::output_tiles: {
      const uint32_t tile = d.size.tile_param.empty() ? d.size.tile
                                                      : size_from_param(decl, params, d.size.tile_param,
                                                                        pass + ": output '" + out.resource + "'");
      if (tile == 0) throw GraphError(pass + ": output '" + out.resource + "' has tiles of 0 pixels");
      desc.extent.width = (settings.width + tile - 1) / tile;
      desc.extent.height = (settings.height + tile - 1) / tile;
      break;
    }
    case SizeRule::Mode::absolute:
      desc.extent.width = d.size.width;
      desc.extent.height = d.size.height;
      break;
    case SizeRule::Mode::like: {
      auto it = known.find(d.size.like);
      if (it == known.end() || it->second.is_buffer)
        throw GraphError(pass + ": output '" + out.resource + "' is sized like unknown image '" + d.size.like + "'");
      desc.extent.width = it->second.extent.width;
      desc.extent.height = it->second.extent.height;
      break;
    }
    case SizeRule::Mode::square_param:
      desc.extent.width = desc.extent.height =
          size_from_param(decl, params, d.size.param, pass + ": output '" + out.resource + "'");
      break;
    case SizeRule::Mode::params:
      desc.extent.width = size_from_param(decl, params, d.size.param, pass + ": output '" + out.resource + "'");
      desc.extent.height = size_from_param(decl, params, d.size.height_param, pass + ": output '" + out.resource + "'");
      break;
  }
  const std::string what = pass + ": output '" + out.resource + "'";
  const uint32_t depth = d.depth_param.empty() ? d.depth : d.depth * size_from_param(decl, params, d.depth_param, what);
  if (d.layers == 0 || depth == 0) throw GraphError(what + " has no layers or no depth");
  if (depth > 1 && d.layers > 1) throw GraphError(what + " is 3D and layered: Vulkan has no 3D arrays");
  if (d.cube && (d.layers % 6 != 0 || desc.extent.width != desc.extent.height))
    throw GraphError(what + " is a cube: it needs square faces and a multiple of 6 layers, not " +
                     std::to_string(desc.extent.width) + "x" + std::to_string(desc.extent.height) + " with " +
                     std::to_string(d.layers));
  desc.cube = d.cube;
  desc.extent.layers = d.layers;
  desc.extent.depth = depth;
  const uint32_t full =
      full_mip_count(std::max(desc.extent.width, desc.extent.depth), std::max(desc.extent.height, desc.extent.depth));
  desc.extent.mips = d.mips == 0 ? full : std::min(d.mips, full);
  return desc;
}

// A declared range made concrete against the image it names; GraphError when it leaves it.
Subresources resolve_range(const Subresources& declared, const ResourceDesc& desc, const std::string& pass,
                           const std::string& resource) {
  if (desc.is_buffer) {
    if (declared != Subresources{})
      throw GraphError(pass + ": '" + resource + "' is a buffer: a use of it has no mips or layers");
    return {0, 1, 0, 1};
  }
  auto concrete = [&](uint32_t base, uint32_t count, uint32_t total, const char* what) {
    if (count == Subresources::kAll) count = base < total ? total - base : 0;
    if (count == 0 || base >= total || count > total - base)
      throw GraphError(pass + ": " + what + " " + std::to_string(base) +
                       (count > 1 ? "-" + std::to_string(base + count - 1) : std::string()) + " of '" + resource +
                       "' is outside the image (" + std::to_string(total) + " " + what + (total == 1 ? "" : "s") + ")");
    return count;
  };
  Subresources range = declared;
  range.mip_count = concrete(declared.base_mip, declared.mip_count, desc.extent.mips, "mip");
  range.layer_count = concrete(declared.base_layer, declared.layer_count, desc.extent.layers, "layer");
  return range;
}

// An injection the executor can carry out: into a float colour image that a GPU pass which runs
// writes, at a texel it has.
void check_nan_injection(const CompiledGraph& graph, const NanInjection& nan) {
  const std::string what = "NaN injection into " + nan.pass + " (" + nan.resource + ")";
  const auto pass = std::find_if(graph.passes.begin(), graph.passes.end(),
                                 [&](const CompiledPass& p) { return p.decl->name == nan.pass; });
  if (pass == graph.passes.end()) throw GraphError(what + ": no such pass");
  if (!pass->runs) throw GraphError(what + ": the pass does not run (" + pass->reason + ")");
  if (pass->decl->type == PassType::cpu) throw GraphError(what + ": a CPU pass (injections are written on the GPU)");
  const auto out = std::find_if(pass->outputs.begin(), pass->outputs.end(),
                                [&](const BoundUse& u) { return u.resource == nan.resource; });
  if (out == pass->outputs.end() || out->desc.is_buffer || !is_float_colour(*format_info(out->desc.format)))
    throw GraphError(what + ": not a float colour image the pass writes");
  if (nan.x >= out->desc.extent.width || nan.y >= out->desc.extent.height)
    throw GraphError(what + ": texel (" + std::to_string(nan.x) + ", " + std::to_string(nan.y) + ") is outside its " +
                     std::to_string(out->desc.extent.width) + "x" + std::to_string(out->desc.extent.height) + " mip 0");
}

// What compile_graph knows, before the frame runs, of each resource's current version: per mip
// and layer, the one value every texel of it holds (a skipped pass's clear value, a fold's
// result). A buffer is one cell.
class KnownValues {
 public:
  void set(const std::string& resource, const Subresources& range, const VkClearValue& value) {
    for_each(range, [&](Cell cell) { cells_[resource][cell] = value; });
  }
  void forget(const std::string& resource, const Subresources& range) {
    for_each(range, [&](Cell cell) { cells_[resource].erase(cell); });
  }
  // The value every cell of `range` holds, if the same one everywhere and known.
  std::optional<VkClearValue> over(const std::string& resource, VkFormat format, const Subresources& range) const {
    auto known = cells_.find(resource);
    if (known == cells_.end()) return std::nullopt;
    std::optional<VkClearValue> value;
    bool uniform = true;
    for_each(range, [&](Cell cell) {
      auto it = known->second.find(cell);
      if (it == known->second.end() || (value && !same_value(format, *value, it->second)))
        uniform = false;
      else
        value = it->second;
    });
    return uniform ? value : std::nullopt;
  }

 private:
  using Cell = std::pair<uint32_t, uint32_t>;  // mip, layer
  static void for_each(const Subresources& range, const std::function<void(Cell)>& visit) {
    for (uint32_t m = range.base_mip; m < range.base_mip + range.mip_count; ++m)
      for (uint32_t l = range.base_layer; l < range.base_layer + range.layer_count; ++l) visit({m, l});
  }
  std::map<std::string, std::map<Cell, VkClearValue>> cells_;
};

Subresources whole_range(const ResourceDesc& desc) {
  return desc.is_buffer ? Subresources{0, 1, 0, 1} : Subresources{0, desc.extent.mips, 0, desc.extent.layers};
}

// The value `resource` holds over the part `declared` names, if known; nothing for a range the
// resource does not have.
std::optional<VkClearValue> known_over(const KnownValues& known, const std::string& resource,
                                       const Subresources& declared,
                                       const std::map<std::string, ResourceDesc>& resources) {
  auto desc = resources.find(resource);
  if (desc == resources.end()) return std::nullopt;
  try {
    return known.over(resource, desc->second.format, resolve_range(declared, desc->second, "", resource));
  } catch (const GraphError&) {
    return std::nullopt;
  }
}

// The part of `resource` the pass reads (or modifies, which reads it too).
Subresources read_range(const PassDecl& decl, const std::string& resource) {
  for (const ResourceUse& in : decl.inputs)
    if (!in.history && !in.prefix && in.resource == resource) return in.range;
  for (const ResourceUse& out : decl.outputs)
    if (out.modifies && out.resource == resource) return out.range;
  return {};
}

// The resources wholly at their declared clear value (PassDecl::skip_when_cleared).
std::set<std::string> cleared_resources(const PassDecl& decl, const KnownValues& known,
                                        const std::map<std::string, ResourceDesc>& resources) {
  std::set<std::string> cleared;
  for (const PassDecl::ClearedSkip& skip : decl.cleared_skips)
    for (const std::string& r : skip.inputs) {
      auto desc = resources.find(r);
      if (desc == resources.end()) continue;
      auto value = known.over(r, desc->second.format, whole_range(desc->second));
      if (value && same_value(desc->second.format, *value, desc->second.clear)) cleared.insert(r);
    }
  return cleared;
}

// What `fold` gives the pass's outputs when the parts of its inputs it reads are uniform and
// known: the value of each fresh output, and of each modified output whose value it changes
// (one it leaves at the value held needs nothing). Nothing when the fold cannot tell or leaves
// an output out.
std::optional<UniformValues> folded_outputs(const PassDecl& decl, const PassDecl::UniformFold& fold,
                                            const KnownValues& known,
                                            const std::map<std::string, ResourceDesc>& resources,
                                            const ParamValues& params) {
  UniformValues inputs;
  for (const std::string& r : fold.inputs) {
    auto value = known_over(known, r, read_range(decl, r), resources);
    if (!value) return std::nullopt;
    inputs[r] = *value;
  }
  std::optional<UniformValues> values = fold.outputs(inputs, params);
  if (!values) return std::nullopt;
  UniformValues changed;
  for (const ResourceUse& out : decl.outputs) {
    auto value = values->find(out.resource);
    if (value == values->end()) return std::nullopt;
    if (out.modifies) {
      auto held = known_over(known, out.resource, out.range, resources);
      if (held && same_value(resources.at(out.resource).format, *held, value->second)) continue;
    }
    changed.insert(*value);
  }
  return changed;
}

}  // namespace

uint32_t full_mip_count(uint32_t width, uint32_t height) {
  return static_cast<uint32_t>(std::bit_width(std::max(width, height)));
}

namespace {

// `passes` without the optional inputs that no pass writes and nothing imports, nor those inputs
// in their fold conditions (the pass computes without them, as a pass whose input holds a known
// value does); nullopt when every optional input is connected.
std::optional<std::vector<PassDecl>> without_unconnected_inputs(const std::vector<PassDecl>& passes,
                                                                const std::vector<ImportedResource>& imports) {
  std::set<std::string> produced;
  for (const ImportedResource& r : imports) produced.insert(r.name);
  for (const PassDecl& pass : passes)
    for (const ResourceUse& out : pass.outputs) produced.insert(out.resource);
  auto unconnected = [&](const ResourceUse& in) { return in.optional && !produced.count(in.resource); };
  if (std::none_of(passes.begin(), passes.end(), [&](const PassDecl& pass) {
        return std::any_of(pass.inputs.begin(), pass.inputs.end(), unconnected);
      }))
    return std::nullopt;
  std::vector<PassDecl> connected = passes;
  for (PassDecl& pass : connected) {
    std::set<std::string> dropped;
    for (const ResourceUse& in : pass.inputs)
      if (unconnected(in)) dropped.insert(in.resource);
    std::erase_if(pass.inputs, unconnected);
    for (PassDecl::UniformFold& fold : pass.uniform_folds)
      std::erase_if(fold.inputs, [&](const std::string& r) { return dropped.count(r) > 0; });
  }
  return connected;
}

// Why the scene, a parameter or the pass's own condition skips it; empty when none does.
std::string skip_reason(const PassDecl& decl, const SkipContext& frame, const GraphSettings& settings,
                        const ParamValues& params) {
  for (const std::string& f : decl.features)
    if (!settings.frame.features.count(f)) return "scene has no " + f;
  if (!decl.disabled_reason.empty() && params.at("enabled") == 0)
    return decl.disabled_reason + " (" + override_key(decl, *decl.find_param("enabled")) + ".enabled=0)";
  return decl.skip_if ? decl.skip_if(frame) : std::string();
}

// A pass whose inputs hold values known before the frame may be skipped for them or folded;
// one that runs learns which of its inputs are uniform.
void use_known_inputs(CompiledPass& compiled, const GraphSettings& settings, const KnownValues& known,
                      const std::map<std::string, ResourceDesc>& resources) {
  const PassDecl& decl = *compiled.decl;
  if (!decl.cleared_skips.empty())
    if (const auto* skip = decl.cleared_skip(cleared_resources(decl, known, resources), compiled.params)) {
      compiled.runs = false;
      compiled.inputs_known = true;
      compiled.reason = skip->reason();
      return;
    }
  // A NaN injected into its output would leave it uniform no longer.
  const bool injected = std::any_of(settings.nan_injections.begin(), settings.nan_injections.end(),
                                    [&](const NanInjection& nan) { return nan.pass == decl.name; });
  if (!injected)
    for (const PassDecl::UniformFold& fold : decl.uniform_folds)
      if (auto values = folded_outputs(decl, fold, known, resources, compiled.params)) {
        compiled.runs = false;
        compiled.inputs_known = true;
        compiled.reason = fold.reason();
        compiled.folded = std::move(*values);
        return;
      }
  for (const ResourceUse& in : decl.inputs)
    if (!in.history && !in.prefix && known_over(known, in.resource, in.range, resources))
      compiled.uniform_inputs.insert(in.resource);
}

// Whether a needed pass runs, and why not.
void decide_whether_runs(CompiledPass& compiled, const GraphSettings& settings, const SkipContext& frame,
                         const KnownValues& known, const std::map<std::string, ResourceDesc>& resources) {
  const PassDecl& decl = *compiled.decl;
  compiled.runs = true;
  // Kept passes are re-executions of what a capture says ran: skip conditions do not apply.
  if (std::find(settings.keep.begin(), settings.keep.end(), decl.name) != settings.keep.end()) return;
  compiled.reason = skip_reason(decl, frame, settings, compiled.params);
  compiled.runs = compiled.reason.empty();
  if (compiled.runs) use_known_inputs(compiled, settings, known, resources);
}

// The versions pass i reads, each with the position of the pass that wrote it.
void bind_inputs(CompiledPass& compiled, int i, const Dependencies& deps,
                 const std::map<std::string, ResourceDesc>& resources, const std::map<int, int>& position) {
  for (const ResourceUse& in : compiled.decl->inputs) {
    if (in.history && !deps.imported.count(previous(in.resource))) {
      // Its description is the resource's, known once its writer is placed (describe_history_inputs).
      compiled.inputs.push_back({previous(in.resource), in.use, false, true, {}, -1, in.range});
      continue;
    }
    for (const std::string& r : deps.reads[i]) {
      const bool matches =
          in.prefix ? r.rfind(in.resource, 0) == 0 : r == (in.history ? previous(in.resource) : in.resource);
      if (!matches) continue;
      int w = deps.version_read_by(i, r);
      compiled.inputs.push_back({r, in.use, false, in.history, resources.at(r), w < 0 ? -1 : position.at(w),
                                 in.prefix ? Subresources{} : in.range});
    }
  }
}

// What pass i writes: a fresh output with its description resolved (now the graph's), a
// modified one with the version it starts from.
void bind_outputs(CompiledPass& compiled, int i, const Dependencies& deps, CompiledGraph& graph,
                  const std::map<int, int>& position) {
  const PassDecl& decl = *compiled.decl;
  for (const ResourceUse& out : decl.outputs) {
    BoundUse bound{out.resource, out.use, out.modifies, false, {}, -1, out.range};
    if (out.modifies) {
      int w = deps.writer_before_modifier(out.resource, i);
      bound.producer = w < 0 ? -1 : position.at(w);
      bound.desc = graph.resources.at(out.resource);
      // A modifier reads the previous version too: that is an input of the pass (once, when
      // the pass also reads other subresources of it).
      const bool read = std::any_of(compiled.inputs.begin(), compiled.inputs.end(),
                                    [&](const BoundUse& in) { return in.resource == out.resource; });
      if (!read) compiled.inputs.push_back(bound);
      bound.producer = -1;
    } else {
      bound.desc = resolve(out, graph.settings, graph.resources, decl, compiled.params);
      graph.resources[out.resource] = bound.desc;
    }
    compiled.outputs.push_back(bound);
  }
}

// A fresh output starts at its declared clear value; what the pass writes is then unknown if
// it runs, or the fold's value.
void update_known_values(KnownValues& known, const CompiledPass& compiled,
                         const std::map<std::string, ResourceDesc>& resources) {
  const PassDecl& decl = *compiled.decl;
  for (const ResourceUse& out : decl.outputs) {
    const ResourceDesc& desc = resources.at(out.resource);
    if (!out.modifies) known.set(out.resource, whole_range(desc), desc.clear);
    auto folded = compiled.folded.find(out.resource);
    if (compiled.runs)
      known.forget(out.resource, resolve_range(out.range, desc, decl.name, out.resource));
    else if (folded != compiled.folded.end())
      known.set(out.resource, resolve_range(out.range, desc, decl.name, out.resource), folded->second);
  }
}

// Each pass in execution order, with what the passes before it decided.
void compile_passes(CompiledGraph& graph, const Dependencies& deps, const std::vector<int>& order,
                    const std::vector<bool>& needed) {
  const GraphSettings& settings = graph.settings;
  SkipContext frame = settings.frame;
  frame.width = settings.width;
  frame.height = settings.height;
  std::map<int, int> position;  // declaration index -> execution index
  // Resources whose current version holds one value everywhere, known before the frame runs: a
  // skipped pass's fresh outputs (their declared clear value) and a folded pass's (the values
  // its fold gave), until a pass that runs writes them.
  KnownValues known;
  for (int i : order) {
    const PassDecl& decl = deps.passes[i];
    CompiledPass compiled;
    compiled.decl = &decl;
    compiled.params = resolve_params(decl, settings.params);
    compiled.clears_if_skipped = deps.clears_if_skipped[i];
    position[i] = static_cast<int>(graph.passes.size());
    if (!needed[i]) {
      compiled.culled = true;
      compiled.reason = "culled: no pass consumes its outputs";
    } else {
      decide_whether_runs(compiled, settings, frame, known, graph.resources);
      bind_inputs(compiled, i, deps, graph.resources, position);
      bind_outputs(compiled, i, deps, graph, position);
      update_known_values(known, compiled, graph.resources);
    }
    graph.passes.push_back(std::move(compiled));
  }
}

// History inputs take the description of the resource they remember, known now that every
// writer is placed.
void describe_history_inputs(CompiledGraph& graph, const std::set<std::string>& imported) {
  for (CompiledPass& pass : graph.passes)
    for (BoundUse& in : pass.inputs) {
      if (!in.history || imported.count(in.resource)) continue;
      // A GPU writer declares every size, so the description is complete; a CPU buffer's size
      // is the kept bytes', known when the frame runs.
      in.desc = graph.resources[in.resource] = graph.resources.at(history_source(in.resource));
    }
}

// Only a pass that runs, or a fold's write, touches its ranges (a skipped pass clears whole
// fresh outputs): a level that does not exist at this output size may be skipped rather than
// be an error.
void resolve_ranges(CompiledGraph& graph) {
  for (CompiledPass& pass : graph.passes)
    for (auto* uses : {&pass.inputs, &pass.outputs})
      for (BoundUse& u : *uses)
        u.range = pass.runs || pass.folded.count(u.resource)
                      ? resolve_range(u.range, u.desc, pass.decl->name, u.resource)
                      : resolve_range({}, u.desc, pass.decl->name, u.resource);
}

CompiledGraph compile_connected(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
                                const GraphSettings& settings) {
  check_overrides(passes, settings.params);
  const Dependencies deps(passes, imports, std::set<std::string>(settings.sinks.begin(), settings.sinks.end()));
  const std::vector<int> order = execution_order(deps);
  const std::vector<bool> needed = needed_passes(deps, settings);
  CompiledGraph graph;
  graph.settings = settings;
  for (const ImportedResource& r : imports) graph.resources[r.name] = r.desc;
  compile_passes(graph, deps, order, needed);
  describe_history_inputs(graph, deps.imported);
  resolve_ranges(graph);
  for (const NanInjection& nan : settings.nan_injections) check_nan_injection(graph, nan);
  plan_synchronisation(graph, deps.imported);
  return graph;
}

}  // namespace

CompiledGraph compile_graph(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
                            const GraphSettings& settings) {
  std::optional<std::vector<PassDecl>> connected = without_unconnected_inputs(passes, imports);
  if (!connected) return compile_connected(passes, imports, settings);
  auto owned = std::make_shared<const std::vector<PassDecl>>(std::move(*connected));
  CompiledGraph graph = compile_connected(*owned, imports, settings);
  graph.connected = std::move(owned);
  return graph;
}

AccessState required_state(Use use, PassType type, bool depth_format) {
  const VkPipelineStageFlags2 shader_stages =
      type == PassType::compute ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
                                : VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
  switch (use) {
    case Use::sampled:
      return {depth_format ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
              shader_stages, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
    case Use::storage_read:
      return {VK_IMAGE_LAYOUT_GENERAL, shader_stages, VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
    case Use::storage_write:
      return {VK_IMAGE_LAYOUT_GENERAL, shader_stages,
              VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
    case Use::color_attachment:
      return {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
              VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case Use::depth_attachment:
      return {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
              VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    case Use::uniform_buffer:
      return {VK_IMAGE_LAYOUT_UNDEFINED, shader_stages, VK_ACCESS_2_UNIFORM_READ_BIT};
    case Use::index_buffer:
      return {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT};
    case Use::indirect_args:
      return {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT};
    case Use::host:
      return {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
  }
  return {};
}

AccessState transfer_state(bool write) {
  return {write ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
          VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, write ? VK_ACCESS_2_TRANSFER_WRITE_BIT : VK_ACCESS_2_TRANSFER_READ_BIT};
}

bool writes(const AccessState& state) {
  constexpr VkAccessFlags2 kWrites = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                     VK_ACCESS_2_HOST_WRITE_BIT;
  return (state.access & kWrites) != 0;
}

std::optional<BarrierPlan> plan_barrier(SyncState& state, const AccessState& next, bool discard) {
  const VkImageLayout old_layout = discard ? VK_IMAGE_LAYOUT_UNDEFINED : state.layout;
  const bool layout_change = next.layout != state.layout;
  const VkPipelineStageFlags2 pending = state.last_write.stages | state.read_stages;
  BarrierPlan plan{{old_layout, pending, state.last_write.access}, next};
  if (writes(next) || layout_change) {
    const bool needed = layout_change || pending != VK_PIPELINE_STAGE_2_NONE;
    state.layout = next.layout;
    // A layout transition is a write of its own: later readers in other stages wait for it.
    state.last_write = writes(next) ? next : AccessState{next.layout, next.stages, VK_ACCESS_2_NONE};
    state.read_stages = writes(next) ? VK_PIPELINE_STAGE_2_NONE : next.stages;
    state.read_access = writes(next) ? VK_ACCESS_2_NONE : next.access;
    if (!needed) return std::nullopt;
    return plan;
  }
  const bool covered = (next.stages & ~state.read_stages) == 0 && (next.access & ~state.read_access) == 0;
  if (state.last_write.stages == VK_PIPELINE_STAGE_2_NONE || covered) return std::nullopt;
  state.read_stages |= next.stages;
  state.read_access |= next.access;
  plan.before = {state.layout, state.last_write.stages, state.last_write.access};
  return plan;
}

}  // namespace nightcap
