// The dependencies between a graph's declarations (dependencies.h).
#include "passes/core/dependencies.h"

#include <algorithm>
#include <queue>

namespace nightcap {
namespace {

// A pass other than passes[writer] that reads `resource` (its next frame's history included)
// and would still run when every list of `skip` is empty, or the frame's caller for a sink;
// empty when there is none.
std::string reader_not_skipped_with(const std::vector<PassDecl>& passes, int writer, const PassDecl::ClearedSkip& skip,
                                    const std::string& resource, const std::set<std::string>& sinks) {
  if (sinks.count(resource)) return "the frame's caller (a sink)";
  auto skips_too = [&](const PassDecl& reader) {
    return std::any_of(reader.cleared_skips.begin(), reader.cleared_skips.end(), [&](const auto& own) {
      return !own.exact && std::all_of(own.inputs.begin(), own.inputs.end(), [&](const std::string& r) {
        return std::find(skip.inputs.begin(), skip.inputs.end(), r) != skip.inputs.end();
      });
    });
  };
  for (int k = 0; k < static_cast<int>(passes.size()); ++k) {
    if (k == writer) continue;
    const PassDecl& reader = passes[k];
    const bool reads = std::any_of(reader.inputs.begin(), reader.inputs.end(),
                                   [&](const ResourceUse& in) {
                                     return in.prefix ? resource.rfind(in.resource, 0) == 0 : in.resource == resource;
                                   }) ||
                       std::any_of(reader.outputs.begin(), reader.outputs.end(),
                                   [&](const ResourceUse& out) { return out.modifies && out.resource == resource; });
    const bool history = std::any_of(reader.inputs.begin(), reader.inputs.end(),
                                     [&](const ResourceUse& in) { return in.history && in.resource == resource; });
    if (history) return reader.name + " (its next frame)";
    if (reads && !skips_too(reader)) return reader.name;
  }
  return {};
}

}  // namespace

int Dependencies::last_writer(const std::string& resource) const {
  auto m = modifiers.find(resource);
  if (m != modifiers.end()) return m->second.back();
  auto f = fresh_writer.find(resource);
  return f == fresh_writer.end() ? -1 : f->second;
}

int Dependencies::writer_before_modifier(const std::string& resource, int modifier) const {
  const std::vector<int>& list = modifiers.at(resource);
  auto it = std::find(list.begin(), list.end(), modifier);
  if (it == list.begin()) {
    auto f = fresh_writer.find(resource);
    return f == fresh_writer.end() ? -1 : f->second;
  }
  return *(it - 1);
}

int Dependencies::version_read_by(int reader, const std::string& resource) const {
  auto m = modifiers.find(resource);
  if (m != modifiers.end() && std::find(m->second.begin(), m->second.end(), reader) != m->second.end())
    return writer_before_modifier(resource, reader);
  return last_writer(resource);
}

Dependencies::Dependencies(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
                           const std::set<std::string>& sinks)
    : passes(passes), reads(passes.size()), history_reads(passes.size()), clears_if_skipped(passes.size(), false) {
  for (const ImportedResource& r : imports) imported.insert(r.name);
  find_writers();
  // Expand prefix reads against everything that exists.
  std::set<std::string> all_names = imported;
  for (const auto& [name, writer] : fresh_writer) all_names.insert(name);
  for (int i = 0; i < static_cast<int>(passes.size()); ++i) {
    clears_if_skipped[i] = check_skips_and_folds(i, sinks);
    find_reads(i, all_names);
  }
}

void Dependencies::find_writers() {
  for (int i = 0; i < static_cast<int>(passes.size()); ++i) {
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
}

// Whether pass i, skipped for a CPU pass's empty list, leaves fresh outputs to clear
// (CompiledPass::clears_if_skipped); GraphError when its skip or fold conditions name what it
// does not read, or leave unwritten what a pass that runs reads.
bool Dependencies::check_skips_and_folds(int i, const std::set<std::string>& sinks) const {
  // A modified output is read too: the pass starts from its previous version.
  auto reads_resource = [&](const std::string& r) {
    return std::any_of(passes[i].inputs.begin(), passes[i].inputs.end(),
                       [&](const ResourceUse& in) { return !in.history && !in.prefix && in.resource == r; }) ||
           std::any_of(passes[i].outputs.begin(), passes[i].outputs.end(),
                       [&](const ResourceUse& out) { return out.modifies && out.resource == r; });
  };
  for (const PassDecl::UniformFold& fold : passes[i].uniform_folds)
    for (const std::string& r : fold.inputs)
      if (!reads_resource(r))
        throw GraphError(passes[i].name + ": folds when '" + r + "' is uniform, but does not read it");
  bool clears_if_skipped = false;
  for (const PassDecl::ClearedSkip& skip : passes[i].cleared_skips)
    for (const std::string& r : skip.inputs) {
      if (!reads_resource(r))
        throw GraphError(passes[i].name + ": skips when '" + r + "' is cleared, but does not read it");
      // A CPU pass's empty list is known only once it has run, after the barriers are planned:
      // a fresh output the pass would leave unwritten must be read by no pass that runs then.
      if (fresh_writer.count(r) && passes[fresh_writer.at(r)].type == PassType::cpu)
        for (const ResourceUse& out : passes[i].outputs)
          if (!out.modifies) {
            if (const std::string reader = reader_not_skipped_with(passes, i, skip, out.resource, sinks);
                !reader.empty())
              throw GraphError(passes[i].name + ": skips when the CPU pass's '" + r + "' is empty, leaving '" +
                               out.resource + "' unwritten, but " + reader +
                               " reads it and does not skip on the same lists");
            clears_if_skipped = true;
          }
    }
  return clears_if_skipped;
}

void Dependencies::find_reads(int i, const std::set<std::string>& all_names) {
  for (const ResourceUse& in : passes[i].inputs) {
    // A resource read in two ways (storage and index buffer, two mips) is one read.
    auto add = [&](const std::string& name) {
      if (std::find(reads[i].begin(), reads[i].end(), name) == reads[i].end()) reads[i].push_back(name);
    };
    if (in.history) {
      if (imported.count(previous(in.resource))) {
        add(previous(in.resource));
      } else if (fresh_writer.count(in.resource)) {
        // The pool keeps a CPU pass's output as bytes, which only a CPU pass reads.
        if (passes[fresh_writer.at(in.resource)].type == PassType::cpu &&
            (passes[i].type != PassType::cpu || in.use != Use::host))
          throw GraphError(passes[i].name + ": reads the previous frame's '" + in.resource +
                           "', a CPU pass's output, on the GPU (only a CPU pass reads a CPU pass's history)");
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

std::vector<int> execution_order(const Dependencies& deps) {
  const int n = static_cast<int>(deps.passes.size());
  std::vector<std::set<int>> successors(n);
  std::vector<int> indegree(n, 0);
  auto add_edge = [&](int from, int to) {
    if (from < 0 || from == to) return;
    if (successors[from].insert(to).second) ++indegree[to];
  };
  for (int i = 0; i < n; ++i) {
    for (const std::string& r : deps.reads[i]) add_edge(deps.version_read_by(i, r), i);
    for (const ResourceUse& out : deps.passes[i].outputs)
      if (out.modifies) add_edge(deps.writer_before_modifier(out.resource, i), i);
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
      if (indegree[i] > 0) stuck += (stuck.empty() ? "" : ", ") + deps.passes[i].name;
    throw GraphError("render graph has a cycle through: " + stuck);
  }
  return order;
}

std::vector<bool> needed_passes(const Dependencies& deps, const GraphSettings& settings) {
  const int n = static_cast<int>(deps.passes.size());
  std::vector<bool> needed(n, false);
  std::vector<int> stack;
  auto need = [&](int w) {
    if (w >= 0 && !needed[w]) {
      needed[w] = true;
      stack.push_back(w);
    }
  };
  for (const std::string& sink : settings.sinks) need(deps.last_writer(sink));
  for (int i = 0; i < n; ++i)
    if (std::find(settings.keep.begin(), settings.keep.end(), deps.passes[i].name) != settings.keep.end()) need(i);
  while (!stack.empty()) {
    int i = stack.back();
    stack.pop_back();
    for (const std::string& r : deps.reads[i]) need(deps.version_read_by(i, r));
    for (const std::string& r : deps.history_reads[i]) need(deps.last_writer(r));
    for (const ResourceUse& out : deps.passes[i].outputs)
      if (out.modifies) need(deps.writer_before_modifier(out.resource, i));
  }
  return needed;
}

}  // namespace nightcap
