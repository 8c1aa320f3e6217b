// The dependencies between a graph's declarations, the first steps of compile_graph: who writes
// and reads each resource, the execution order that gives, and the passes a frame needs (the
// others are culled). Internal to passes/core.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "passes/core/graph.h"

namespace nightcap {

// Who writes and reads what, from the declarations alone: what orders the passes and decides
// which are needed. Indices are into the declarations.
struct Dependencies {
  // GraphError for a name with '@', a GPU buffer without a declared size, two fresh writers, a
  // modify with no earlier version, a read or history of what nobody writes, a CPU pass's history
  // read on the GPU, and skip or fold conditions on what the pass does not read.
  Dependencies(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
               const std::set<std::string>& sinks);

  const std::vector<PassDecl>& passes;
  std::set<std::string> imported;
  // Who writes what: fresh writer first, then modifiers in declaration order.
  std::map<std::string, int> fresh_writer;
  std::map<std::string, std::vector<int>> modifiers;
  std::vector<std::vector<std::string>> reads;  // per pass, once each, prefix reads expanded
  // History reads: the resource whose previous value each pass reads from the pool. They order
  // nothing this frame; they keep the resource's writer running.
  std::vector<std::vector<std::string>> history_reads;
  std::vector<bool> clears_if_skipped;  // per pass (CompiledPass::clears_if_skipped)

  // The version a pass reads: plain readers see the last version; a modifier sees the one
  // before it. Edges point from the writer of that version to the reader.
  int last_writer(const std::string& resource) const;
  int writer_before_modifier(const std::string& resource, int modifier) const;
  // A pass that modifies a resource and also reads it (another mip, say) reads the version
  // before its own.
  int version_read_by(int reader, const std::string& resource) const;

 private:
  void find_writers();
  bool check_skips_and_folds(int i, const std::set<std::string>& sinks) const;
  void find_reads(int i, const std::set<std::string>& all_names);
};

// Declaration indices in execution order; GraphError for a cycle.
std::vector<int> execution_order(const Dependencies& deps);

// Needed: passes that lead to a sink or are kept.
std::vector<bool> needed_passes(const Dependencies& deps, const GraphSettings& settings);

}  // namespace nightcap
