// What one pass of a rendered frame read and wrote, by resource, as run_isolated takes its
// inputs: for tests and the benchmark that check a pass on its recorded inputs.
#pragma once

#include <map>
#include <string>

#include "passes/assembly/renderer.h"
#include "passes/core/isolated.h"

namespace nightcap {

struct RecordedPass {
  std::map<std::string, IsolatedInput> inputs, outputs;
};

// Empty when the frame has no pass of that name; a pass that did not run has no outputs.
inline RecordedPass recorded_pass(const RenderedFrame& frame, const std::string& pass) {
  RecordedPass r;
  for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
    if (frame.graph.passes[i].decl->name != pass) continue;
    for (int v : frame.execution.passes[i].inputs) {
      const VersionData& d = frame.execution.versions[v];
      r.inputs[d.resource] = {d.desc, d.bytes};
    }
    for (int v : frame.execution.passes[i].outputs) {
      const VersionData& d = frame.execution.versions[v];
      r.outputs[d.resource] = {d.desc, d.bytes};
    }
  }
  return r;
}

}  // namespace nightcap
