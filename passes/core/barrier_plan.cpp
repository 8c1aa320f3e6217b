// The barrier plan, part of the compile step: every barrier, clear, upload and readback of a
// frame decided from the compiled graph alone, so the executor only issues it and a unit test
// can check it. Each mip and layer of an image is tracked on its own (a pass may sample mip
// i - 1 while writing mip i), and barriers are merged back into rectangles of subresources that
// move between the same states, so a whole-image use stays one barrier.
#include <algorithm>

#include "passes/core/graph.h"

namespace nightcap {
namespace {

// One value per (mip, layer) of a resource; a buffer is a 1×1 grid.
template <typename T>
struct Grid {
  uint32_t mips = 1, layers = 1;
  std::vector<T> cells;
  explicit Grid(const ResourceDesc& desc)
      : mips(desc.is_buffer ? 1 : desc.extent.mips),
        layers(desc.is_buffer ? 1 : desc.extent.layers),
        cells(size_t(mips) * layers) {}
  T& at(uint32_t m, uint32_t l) { return cells[size_t(m) * layers + l]; }
};

// Covers the set cells of a grid with rectangles of equal values: runs of layers per mip, then
// runs of mips with the same layer runs.
template <typename T>
std::vector<std::pair<Subresources, T>> rectangles(Grid<std::optional<T>>& grid) {
  std::vector<std::pair<Subresources, T>> done, open;
  for (uint32_t m = 0; m < grid.mips; ++m) {
    std::vector<std::pair<Subresources, T>> next;
    for (uint32_t l = 0; l < grid.layers;) {
      if (!grid.at(m, l)) {
        ++l;
        continue;
      }
      uint32_t end = l + 1;
      while (end < grid.layers && grid.at(m, end) && *grid.at(m, end) == *grid.at(m, l)) ++end;
      auto same = std::find_if(open.begin(), open.end(), [&](const auto& r) {
        return r.first.base_layer == l && r.first.layer_count == end - l && r.second == *grid.at(m, l);
      });
      if (same != open.end()) {
        ++same->first.mip_count;
        next.push_back(*same);
        open.erase(same);
      } else {
        next.push_back({Subresources{m, 1, l, end - l}, *grid.at(m, l)});
      }
      l = end;
    }
    done.insert(done.end(), open.begin(), open.end());
    open = std::move(next);
  }
  done.insert(done.end(), open.begin(), open.end());
  return done;
}

struct Need {
  AccessState state;
  bool discard = true;  // every use of the subresource in this step ignores its contents
  bool operator==(const Need&) const = default;
};

class Planner {
 public:
  explicit Planner(const CompiledGraph& graph) : graph_(graph) {}

  // Adds a use to the current step. Uses of one subresource within a step must agree on its
  // layout; their stages and accesses add up.
  void use(const std::string& resource, const Subresources& range, AccessState state, bool discard,
           const std::string& pass) {
    const ResourceDesc& desc = graph_.resources.at(resource);
    if (desc.is_buffer) state.layout = VK_IMAGE_LAYOUT_UNDEFINED;  // buffers have none
    auto it = step_.try_emplace(resource, Grid<std::optional<Need>>(desc)).first;
    Lifetime& lifetime = lifetimes_[resource];
    if (lifetime.first < 0) lifetime.first = steps_;
    lifetime.last = steps_;
    for (uint32_t m = range.base_mip; m < range.base_mip + range.mip_count; ++m)
      for (uint32_t l = range.base_layer; l < range.base_layer + range.layer_count; ++l) {
        std::optional<Need>& need = it->second.at(m, l);
        if (!need) {
          need = Need{state, discard};
          continue;
        }
        if (need->state.layout != state.layout)
          throw GraphError(pass + ": uses mip " + std::to_string(m) + " layer " + std::to_string(l) + " of '" +
                           resource + "' in two layouts at once (e.g. sampled and as an attachment)");
        need->state.stages |= state.stages;
        need->state.access |= state.access;
        need->discard = need->discard && discard;
      }
  }
  void use_whole(const std::string& resource, const AccessState& state, bool discard) {
    use(resource, whole(resource), state, discard, "");
  }

  // The barriers the current step needs, given everything planned before it.
  std::vector<PlannedBarrier> flush() {
    std::vector<PlannedBarrier> barriers;
    for (auto& [resource, needs] : step_) {
      const ResourceDesc& desc = graph_.resources.at(resource);
      auto state = states_.try_emplace(resource, Grid<Cell>(desc)).first;
      Grid<std::optional<std::pair<BarrierPlan, bool>>> plans(desc);  // and whether it is a first use
      for (uint32_t m = 0; m < needs.mips; ++m)
        for (uint32_t l = 0; l < needs.layers; ++l)
          if (const std::optional<Need>& need = needs.at(m, l)) {
            Cell& cell = state->second.at(m, l);
            std::optional<BarrierPlan> plan = plan_barrier(cell.sync, need->state, need->discard);
            if (!cell.used)
              plans.at(m, l) = {plan.value_or(BarrierPlan{{}, need->state}), true};
            else if (plan)
              plans.at(m, l) = {*plan, false};
            cell.used = true;
          }
      for (auto& [range, plan] : rectangles(plans)) barriers.push_back({resource, range, plan.first, plan.second});
    }
    step_.clear();
    ++steps_;
    return barriers;
  }

  // Each resource's lifetime, with the state its last step left it in.
  std::map<std::string, Lifetime> lifetimes() {
    for (auto& [resource, lifetime] : lifetimes_) {
      lifetime.last_use = {};
      for (const Cell& cell : states_.at(resource).cells) {
        lifetime.last_use.stages |= cell.sync.last_write.stages | cell.sync.read_stages;
        lifetime.last_use.access |= cell.sync.last_write.access;
      }
    }
    return lifetimes_;
  }

  Subresources whole(const std::string& resource) const {
    const ResourceDesc& desc = graph_.resources.at(resource);
    return desc.is_buffer ? Subresources{0, 1, 0, 1} : Subresources{0, desc.extent.mips, 0, desc.extent.layers};
  }

 private:
  struct Cell {
    SyncState sync;
    bool used = false;  // by an earlier step
  };
  const CompiledGraph& graph_;
  std::map<std::string, Grid<Cell>> states_;
  std::map<std::string, Grid<std::optional<Need>>> step_;
  int steps_ = 0;  // flushed so far
  std::map<std::string, Lifetime> lifetimes_;
};

bool on_gpu(const CompiledPass& pass) { return !pass.culled && pass.decl->type != PassType::cpu; }

// Whether the pass leaves a new version of the output (a skipped modifier leaves none, unless
// its fold gives the part it modifies a new value).
bool versions(const CompiledPass& pass, const BoundUse& out) {
  return pass.runs || !out.modifies || pass.folded.count(out.resource);
}

// The history slots whose resource ends the frame at its declared clear value: its fresh writer
// skips, and so does every pass that modifies it after, none folding it. The pool needs no copy
// for them (HistorySlot::at_clear_value).
std::set<std::string> history_at_clear_value(const CompiledGraph& graph) {
  std::map<std::string, bool> at_clear;  // resource -> whether its current version is the clear value
  for (const CompiledPass& pass : graph.passes) {
    if (pass.culled) continue;
    for (const BoundUse& out : pass.outputs) {
      if (!versions(pass, out)) continue;
      at_clear[out.resource] =
          !pass.runs && pass.decl->type != PassType::cpu && !out.modifies && !pass.folded.count(out.resource);
    }
  }
  std::set<std::string> slots;
  for (const std::string& slot : graph.history)
    if (at_clear[history_source(slot)]) slots.insert(slot);
  return slots;
}

// The versions skipped GPU passes leave (their outputs, by pass index) that something reads: a
// pass that runs, a readback, the history copy. The others need no clear. A fold that changes
// part of a modified output builds on the version before it, which is then read too.
std::set<std::pair<size_t, std::string>> read_skipped_versions(const CompiledGraph& graph) {
  std::set<std::pair<size_t, std::string>> read;
  // resource -> the skipped passes whose clears make up its current version
  std::map<std::string, std::vector<size_t>> current;
  auto reads = [&](const std::string& resource) {
    if (auto it = current.find(resource); it != current.end())
      for (size_t writer : it->second) read.insert({writer, resource});
  };
  for (size_t i = 0; i < graph.passes.size(); ++i) {
    const CompiledPass& pass = graph.passes[i];
    if (pass.culled) continue;
    if (pass.runs) {
      for (const BoundUse& in : pass.inputs)
        if (!in.history) reads(in.resource);
      for (const BoundUse& out : pass.outputs)
        if (out.modifies) reads(out.resource);
    }
    for (const BoundUse& out : pass.outputs) {
      if (!versions(pass, out)) continue;
      if (pass.runs || pass.decl->type == PassType::cpu) {
        current.erase(out.resource);
        continue;
      }
      if (!out.modifies) current[out.resource].clear();
      current[out.resource].push_back(i);
      if (graph.settings.capture) reads(out.resource);
    }
  }
  for (const std::string& resource : graph.settings.readback) reads(resource);
  for (const std::string& slot : graph.history)
    if (!graph.history_at_clear_value.count(slot)) reads(history_source(slot));
  return read;
}

}  // namespace

void plan_synchronisation(CompiledGraph& graph, const std::set<std::string>& imports) {
  Planner planner(graph);
  std::set<std::string> used_on_gpu;
  for (const CompiledPass& pass : graph.passes)
    if (on_gpu(pass))
      for (const auto* uses : {&pass.inputs, &pass.outputs})
        for (const BoundUse& u : *uses) used_on_gpu.insert(u.resource);
  graph.uploads.clear();
  for (const std::string& resource : used_on_gpu)
    if (imports.count(resource)) {
      graph.uploads.push_back(resource);
      planner.use_whole(resource, transfer_state(true), true);
    }
  graph.before_uploads = planner.flush();

  graph.history.clear();
  for (const CompiledPass& pass : graph.passes)
    if (on_gpu(pass))
      for (const BoundUse& in : pass.inputs)
        if (in.history && !imports.count(in.resource) &&
            std::find(graph.history.begin(), graph.history.end(), in.resource) == graph.history.end())
          graph.history.push_back(in.resource);
  for (const std::string& slot : graph.history) planner.use_whole(slot, transfer_state(true), true);
  graph.before_history_clears = planner.flush();
  if (graph.settings.capture)
    for (const std::string& slot : graph.history) planner.use_whole(slot, transfer_state(false), false);
  graph.before_history_readback = planner.flush();
  graph.history_at_clear_value = history_at_clear_value(graph);

  std::map<std::string, size_t> final_writer;
  for (size_t i = 0; i < graph.passes.size(); ++i)
    if (on_gpu(graph.passes[i]))
      for (const BoundUse& out : graph.passes[i].outputs)
        if (versions(graph.passes[i], out)) final_writer[out.resource] = i;
  const std::set<std::pair<size_t, std::string>> read_skipped = read_skipped_versions(graph);
  // A version's bytes are on the host when it is imported or a CPU pass wrote it (a CPU pass's
  // history too: the pool keeps it as bytes).
  std::set<std::string> cpu_written;
  for (const CompiledPass& pass : graph.passes)
    if (!pass.culled && pass.decl->type == PassType::cpu)
      for (const BoundUse& out : pass.outputs) cpu_written.insert(out.resource);
  auto on_host = [&](const BoundUse& in) {
    if (in.history) return imports.count(in.resource) > 0 || cpu_written.count(history_source(in.resource)) > 0;
    return in.producer < 0 || graph.passes[size_t(in.producer)].decl->type == PassType::cpu;
  };

  for (size_t i = 0; i < graph.passes.size(); ++i) {
    CompiledPass& pass = graph.passes[i];
    PassSync& sync = pass.sync;
    sync = {};
    if (pass.culled) continue;
    if (pass.decl->type == PassType::cpu) {
      if (pass.runs && !graph.settings.capture)
        for (const BoundUse& in : pass.inputs)
          if (!on_host(in) &&
              std::find(sync.host_reads.begin(), sync.host_reads.end(), in.resource) == sync.host_reads.end()) {
            sync.host_reads.push_back(in.resource);
            planner.use_whole(in.resource, transfer_state(false), false);
          }
      sync.before_host_reads = planner.flush();
      for (const BoundUse& out : pass.outputs)
        if (used_on_gpu.count(out.resource)) {
          sync.uploads.push_back(out.resource);
          planner.use_whole(out.resource, transfer_state(true), true);
        }
      sync.before_uploads = planner.flush();
      continue;
    }
    // Fresh outputs start defined: a skipped pass's wholly, a running pass's outside the part it
    // writes. A folded pass's write sets the part it names to the fold's value.
    for (const BoundUse& out : pass.outputs) {
      auto folded = pass.folded.find(out.resource);
      const bool fold_writes = !pass.runs && folded != pass.folded.end();
      if ((out.modifies && !fold_writes) || (!pass.runs && !read_skipped.count({i, out.resource}))) continue;
      // Per subresource: true for the fold's value, false for the declared clear value.
      Grid<std::optional<bool>> cleared(out.desc);
      for (uint32_t m = 0; m < cleared.mips; ++m)
        for (uint32_t l = 0; l < cleared.layers; ++l)
          if (out.range.contains(m, l)) {
            if (!pass.runs) cleared.at(m, l) = fold_writes;
          } else if (!out.modifies) {
            cleared.at(m, l) = false;
          }
      for (auto& [range, fold_value] : rectangles(cleared)) {
        sync.clears.push_back({out.resource, range, fold_value ? folded->second : out.desc.clear});
        planner.use(out.resource, range, transfer_state(true), true, pass.decl->name);
      }
      // What it writes, in case an empty list skips it; the pass keeps the clear if it runs.
      if (pass.runs && pass.clears_if_skipped && !out.modifies) {
        Grid<std::optional<bool>> written(out.desc);
        for (uint32_t m = 0; m < written.mips; ++m)
          for (uint32_t l = 0; l < written.layers; ++l)
            if (out.range.contains(m, l)) written.at(m, l) = false;
        for (auto& [range, unused] : rectangles(written)) {
          sync.clears.push_back({out.resource, range, out.desc.clear, true});
          planner.use(out.resource, range, transfer_state(true), true, pass.decl->name);
        }
      }
    }
    sync.before_clears = planner.flush();
    if (pass.runs) {
      const PassType type = pass.decl->type;
      auto depth = [](const BoundUse& u) { return !u.desc.is_buffer && format_info(u.desc.format)->is_depth; };
      for (const BoundUse& in : pass.inputs)
        if (!in.modifies && in.use != Use::host)
          planner.use(in.resource, in.range, required_state(in.use, type, depth(in)), false, pass.decl->name);
      for (const BoundUse& out : pass.outputs)
        planner.use(out.resource, out.range, required_state(out.use, type, depth(out)),
                    !out.modifies && !pass.clears_if_skipped, pass.decl->name);
      sync.before_pass = planner.flush();
      for (const NanInjection& nan : graph.settings.nan_injections)
        if (nan.pass == pass.decl->name) {
          sync.injections.push_back(nan);
          // One texel of the subresource changes: the rest keeps what the pass wrote.
          planner.use(nan.resource, Subresources::at(0, 0), transfer_state(true), false, pass.decl->name);
        }
      sync.before_injections = planner.flush();
    }
    for (const BoundUse& out : pass.outputs) {
      if (!versions(pass, out)) continue;
      if (graph.settings.capture ||
          (final_writer.at(out.resource) == i && graph.settings.readback.count(out.resource))) {
        sync.readback.push_back(out.resource);
        planner.use_whole(out.resource, transfer_state(false), false);
      }
    }
    sync.before_readback = planner.flush();
  }

  for (const std::string& slot : graph.history) {
    // A slot not copied into keeps its bytes: the pool may already hold the clear value there.
    const bool copied = !graph.history_at_clear_value.count(slot);
    if (copied) planner.use_whole(history_source(slot), transfer_state(false), false);
    planner.use_whole(slot, transfer_state(true), copied);
  }
  graph.before_history_copy = planner.flush();
  graph.lifetimes = planner.lifetimes();
}

}  // namespace nightcap
