#include "passes/core/graph.h"

#include <algorithm>
#include <bit>
#include <map>
#include <queue>
#include <set>

namespace nightcap {
namespace {

struct Version {
  int writer = -1;  // declaration index; -1 imported
  ResourceDesc desc;
};

ResourceDesc resolve(const ResourceUse& out, const GraphSettings& settings,
                     const std::map<std::string, ResourceDesc>& known, const std::string& pass) {
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
    case SizeRule::Mode::output_tiles:
      if (d.size.tile == 0) throw GraphError(pass + ": output '" + out.resource + "' has tiles of 0 pixels");
      desc.extent.width = (settings.width + d.size.tile - 1) / d.size.tile;
      desc.extent.height = (settings.height + d.size.tile - 1) / d.size.tile;
      break;
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
  }
  const std::string what = pass + ": output '" + out.resource + "'";
  if (d.layers == 0 || d.depth == 0) throw GraphError(what + " has no layers or no depth");
  if (d.depth > 1 && d.layers > 1) throw GraphError(what + " is 3D and layered: Vulkan has no 3D arrays");
  if (d.cube && (d.layers % 6 != 0 || desc.extent.width != desc.extent.height))
    throw GraphError(what + " is a cube: it needs square faces and a multiple of 6 layers, not " +
                     std::to_string(desc.extent.width) + "x" + std::to_string(desc.extent.height) + " with " +
                     std::to_string(d.layers));
  desc.cube = d.cube;
  desc.extent.layers = d.layers;
  desc.extent.depth = d.depth;
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

}  // namespace

uint32_t full_mip_count(uint32_t width, uint32_t height) {
  return static_cast<uint32_t>(std::bit_width(std::max(width, height)));
}

CompiledGraph compile_graph(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
                            const GraphSettings& settings) {
  const int n = static_cast<int>(passes.size());
  // Who writes what: fresh writer first, then modifiers in declaration order.
  std::map<std::string, int> fresh_writer;
  std::map<std::string, std::vector<int>> modifiers;
  std::set<std::string> imported;
  for (const ImportedResource& r : imports) imported.insert(r.name);
  for (int i = 0; i < n; ++i) {
    for (const ResourceUse& out : passes[i].outputs) {
      if (out.resource.find('@') != std::string::npos)
        throw GraphError(passes[i].name + ": '" + out.resource + "': '@' is reserved for history (read_previous)");
      if (out.is_buffer && !out.modifies && out.buffer.size == 0 && passes[i].type != PassType::cpu)
        throw GraphError(passes[i].name + ": GPU buffer '" + out.resource +
                         "' has no declared size (only a CPU pass may size its output when it runs)");
      if (out.modifies) {
        modifiers[out.resource].push_back(i);
      } else {
        if (fresh_writer.count(out.resource) || imported.count(out.resource))
          throw GraphError(
              passes[i].name + ": '" + out.resource + "' is already written by " +
              (imported.count(out.resource) ? std::string("the scene") : passes[fresh_writer[out.resource]].name) +
              " (use modify to write it again)");
        fresh_writer[out.resource] = i;
      }
    }
  }
  for (const auto& [resource, list] : modifiers)
    if (!fresh_writer.count(resource) && !imported.count(resource))
      throw GraphError(passes[list.front()].name + ": modifies '" + resource + "' which nobody writes first");

  // Expand prefix reads against everything that exists.
  std::set<std::string> all_names = imported;
  for (const auto& [name, writer] : fresh_writer) all_names.insert(name);
  std::vector<std::vector<std::string>> reads(n);
  // History reads: the resource whose previous value each pass reads from the pool. They order
  // nothing this frame; they keep the resource's writer running.
  std::vector<std::vector<std::string>> history_reads(n);
  for (int i = 0; i < n; ++i) {
    for (const PassDecl::ClearedSkip& skip : passes[i].cleared_skips)
      for (const std::string& r : skip.inputs) {
        // A modified output is read too: the pass starts from its previous version.
        if (std::none_of(passes[i].inputs.begin(), passes[i].inputs.end(),
                         [&](const ResourceUse& in) { return !in.history && !in.prefix && in.resource == r; }) &&
            std::none_of(passes[i].outputs.begin(), passes[i].outputs.end(),
                         [&](const ResourceUse& out) { return out.modifies && out.resource == r; }))
          throw GraphError(passes[i].name + ": skips when '" + r + "' is cleared, but does not read it");
        // A CPU pass's empty list is known only once it has run, after the barriers are planned.
        if (fresh_writer.count(r) && passes[fresh_writer.at(r)].type == PassType::cpu)
          for (const ResourceUse& out : passes[i].outputs)
            if (!out.modifies)
              throw GraphError(passes[i].name + ": skips when the CPU pass's '" + r +
                               "' is empty, so it may only modify its outputs, but it writes '" + out.resource + "'");
      }
    for (const ResourceUse& in : passes[i].inputs) {
      // A resource read in two ways (storage and index buffer, two mips) is one read.
      auto add = [&](const std::string& name) {
        if (std::find(reads[i].begin(), reads[i].end(), name) == reads[i].end()) reads[i].push_back(name);
      };
      if (in.history) {
        if (imported.count(previous(in.resource))) {
          add(previous(in.resource));
        } else if (fresh_writer.count(in.resource)) {
          if (passes[fresh_writer.at(in.resource)].type == PassType::cpu)
            throw GraphError(passes[i].name + ": reads the previous frame's '" + in.resource +
                             "', a CPU pass's output (the history pool keeps GPU resources)");
          history_reads[i].push_back(in.resource);
        } else {
          throw GraphError(passes[i].name + ": reads the previous frame's '" + in.resource + "', which no pass writes");
        }
      } else if (in.prefix) {
        for (const std::string& name : all_names)
          if (name.rfind(in.resource, 0) == 0) add(name);
      } else {
        if (!all_names.count(in.resource))
          throw GraphError(passes[i].name + ": reads '" + in.resource +
                           "' which no pass writes and the scene does not supply");
        add(in.resource);
      }
    }
  }

  // The version a pass reads: plain readers see the last version; a modifier sees the one
  // before it. Edges point from the writer of that version to the reader.
  auto last_writer = [&](const std::string& resource) {
    auto m = modifiers.find(resource);
    if (m != modifiers.end()) return m->second.back();
    auto f = fresh_writer.find(resource);
    return f == fresh_writer.end() ? -1 : f->second;
  };
  auto writer_before_modifier = [&](const std::string& resource, int modifier) {
    const std::vector<int>& list = modifiers[resource];
    auto it = std::find(list.begin(), list.end(), modifier);
    if (it == list.begin()) {
      auto f = fresh_writer.find(resource);
      return f == fresh_writer.end() ? -1 : f->second;
    }
    return *(it - 1);
  };
  // A pass that modifies a resource and also reads it (another mip, say) reads the version
  // before its own.
  auto version_read_by = [&](int reader, const std::string& resource) {
    auto m = modifiers.find(resource);
    if (m != modifiers.end() && std::find(m->second.begin(), m->second.end(), reader) != m->second.end())
      return writer_before_modifier(resource, reader);
    return last_writer(resource);
  };
  std::vector<std::set<int>> successors(n);
  std::vector<int> indegree(n, 0);
  auto add_edge = [&](int from, int to) {
    if (from < 0 || from == to) return;
    if (successors[from].insert(to).second) ++indegree[to];
  };
  for (int i = 0; i < n; ++i) {
    for (const std::string& r : reads[i]) add_edge(version_read_by(i, r), i);
    for (const ResourceUse& out : passes[i].outputs)
      if (out.modifies) add_edge(writer_before_modifier(out.resource, i), i);
  }

  // Kahn's algorithm; ties keep declaration (frame) order.
  std::priority_queue<int, std::vector<int>, std::greater<>> ready;
  for (int i = 0; i < n; ++i)
    if (indegree[i] == 0) ready.push(i);
  std::vector<int> order;
  while (!ready.empty()) {
    int i = ready.top();
    ready.pop();
    order.push_back(i);
    for (int s : successors[i])
      if (--indegree[s] == 0) ready.push(s);
  }
  if (static_cast<int>(order.size()) != n) {
    std::string stuck;
    for (int i = 0; i < n; ++i)
      if (indegree[i] > 0) stuck += (stuck.empty() ? "" : ", ") + passes[i].name;
    throw GraphError("render graph has a cycle through: " + stuck);
  }

  // Needed: passes that lead to a sink or are kept.
  std::vector<bool> needed(n, false);
  std::vector<int> stack;
  auto need_writers_of = [&](const std::string& resource) {
    int w = last_writer(resource);
    if (w >= 0 && !needed[w]) {
      needed[w] = true;
      stack.push_back(w);
    }
  };
  for (const std::string& sink : settings.sinks) need_writers_of(sink);
  for (int i = 0; i < n; ++i)
    if (std::find(settings.keep.begin(), settings.keep.end(), passes[i].name) != settings.keep.end() && !needed[i]) {
      needed[i] = true;
      stack.push_back(i);
    }
  while (!stack.empty()) {
    int i = stack.back();
    stack.pop_back();
    auto need = [&](int w) {
      if (w >= 0 && !needed[w]) {
        needed[w] = true;
        stack.push_back(w);
      }
    };
    for (const std::string& r : reads[i]) need(version_read_by(i, r));
    for (const std::string& r : history_reads[i]) need(last_writer(r));
    for (const ResourceUse& out : passes[i].outputs)
      if (out.modifies) need(writer_before_modifier(out.resource, i));
  }

  CompiledGraph graph;
  graph.settings = settings;
  for (const ImportedResource& r : imports) graph.resources[r.name] = r.desc;
  SkipContext frame = settings.frame;
  frame.width = settings.width;
  frame.height = settings.height;
  std::map<int, int> position;  // declaration index -> execution index
  // Resources whose current version holds its declared clear value: a skipped pass's fresh
  // outputs, until a pass that runs writes them.
  std::set<std::string> cleared;
  for (int i : order) {
    const PassDecl& decl = passes[i];
    CompiledPass compiled;
    compiled.decl = &decl;
    position[i] = static_cast<int>(graph.passes.size());
    if (!needed[i]) {
      compiled.culled = true;
      compiled.reason = "culled: no pass consumes its outputs";
    } else if (std::find(settings.keep.begin(), settings.keep.end(), decl.name) != settings.keep.end()) {
      // Kept passes are re-executions of what a capture says ran: skip conditions do not apply.
      compiled.runs = true;
    } else {
      compiled.runs = true;
      for (const std::string& f : decl.features)
        if (!settings.frame.features.count(f)) {
          compiled.runs = false;
          compiled.reason = "scene has no " + f;
          break;
        }
      if (compiled.runs && !decl.disabled_reason.empty()) {
        auto params = settings.params.find(decl.disable_switch);
        if (params != settings.params.end() && params->second.count("enabled") && params->second.at("enabled") == 0) {
          compiled.runs = false;
          compiled.reason = decl.disabled_reason + " (" + decl.disable_switch + ".enabled=0)";
        }
      }
      if (compiled.runs && decl.skip_if) {
        compiled.reason = decl.skip_if(frame);
        compiled.runs = compiled.reason.empty();
      }
      if (compiled.runs && !decl.cleared_skips.empty())
        if (const auto* skip = decl.cleared_skip(cleared, decl.params_with(settings.params))) {
          compiled.runs = false;
          compiled.inputs_cleared = true;
          compiled.reason = skip->reason();
        }
    }
    for (const ResourceUse& out : decl.outputs) {
      if (compiled.culled || (out.modifies && !compiled.runs)) continue;
      if (compiled.runs)
        cleared.erase(out.resource);
      else
        cleared.insert(out.resource);
    }
    if (!compiled.culled) {
      for (size_t k = 0; k < decl.inputs.size(); ++k) {
        const ResourceUse& in = decl.inputs[k];
        if (in.history && !imported.count(previous(in.resource))) {
          // Its description is the resource's, known once its writer is placed (below).
          compiled.inputs.push_back({previous(in.resource), in.use, false, true, {}, -1, in.range});
          continue;
        }
        for (const std::string& r : reads[i]) {
          const bool matches =
              in.prefix ? r.rfind(in.resource, 0) == 0 : r == (in.history ? previous(in.resource) : in.resource);
          if (!matches) continue;
          int w = version_read_by(i, r);
          compiled.inputs.push_back({r, in.use, false, in.history, graph.resources.at(r), w < 0 ? -1 : position.at(w),
                                     in.prefix ? Subresources{} : in.range});
        }
      }
      for (const ResourceUse& out : decl.outputs) {
        BoundUse bound{out.resource, out.use, out.modifies, false, {}, -1, out.range};
        if (out.modifies) {
          int w = writer_before_modifier(out.resource, i);
          bound.producer = w < 0 ? -1 : position.at(w);
          bound.desc = graph.resources.at(out.resource);
          // A modifier reads the previous version too: that is an input of the pass (once, when
          // the pass also reads other subresources of it).
          const bool read = std::any_of(compiled.inputs.begin(), compiled.inputs.end(),
                                        [&](const BoundUse& in) { return in.resource == out.resource; });
          if (!read) compiled.inputs.push_back(bound);
          bound.producer = -1;
        } else {
          bound.desc = resolve(out, settings, graph.resources, decl.name);
          graph.resources[out.resource] = bound.desc;
        }
        compiled.outputs.push_back(bound);
      }
    }
    graph.passes.push_back(std::move(compiled));
  }
  // History inputs take the description of the resource they remember, known now that every
  // writer is placed.
  for (CompiledPass& pass : graph.passes)
    for (BoundUse& in : pass.inputs) {
      if (!in.history || imported.count(in.resource)) continue;
      // A GPU writer declares every size, so the description is complete.
      in.desc = graph.resources[in.resource] = graph.resources.at(history_source(in.resource));
    }
  // Only a pass that runs touches its ranges (a skipped one clears whole fresh outputs): a
  // level that does not exist at this output size may be skipped rather than be an error.
  for (CompiledPass& pass : graph.passes)
    for (auto* uses : {&pass.inputs, &pass.outputs})
      for (BoundUse& u : *uses)
        u.range = pass.runs ? resolve_range(u.range, u.desc, pass.decl->name, u.resource)
                            : resolve_range({}, u.desc, pass.decl->name, u.resource);
  for (const NanInjection& nan : settings.nan_injections) check_nan_injection(graph, nan);
  plan_synchronisation(graph, imported);
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
