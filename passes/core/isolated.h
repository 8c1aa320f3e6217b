// One pass run on its own from given inputs: what replay and the reference tests do.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "passes/core/executor.h"

namespace nightcap {

struct IsolatedInput {
  ResourceDesc desc;
  std::shared_ptr<const std::vector<uint8_t>> bytes;
};

// A buffer input holding `bytes` (empty: what a skipped CPU pass leaves), and one holding a record.
IsolatedInput buffer_input(std::span<const uint8_t> bytes);
template <typename Record>
IsolatedInput record_input(const Record& record) {
  static_assert(std::is_trivially_copyable_v<Record>);
  return buffer_input({reinterpret_cast<const uint8_t*>(&record), sizeof record});
}
// One holding `records` back to back.
template <typename Record>
IsolatedInput records_input(std::span<const Record> records) {
  static_assert(std::is_trivially_copyable_v<Record>);
  return buffer_input({reinterpret_cast<const uint8_t*>(records.data()), records.size_bytes()});
}

struct IsolatedRun {
  std::shared_ptr<const std::vector<PassDecl>> declaration;  // the one pass graph.passes' decl names
  CompiledGraph graph;
  Execution execution;
  // Output bytes of the pass, by resource name.
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> outputs;
  std::map<std::string, ResourceDesc> output_descs;
};

// Runs `pass` (whatever its skip conditions say) at output size width×height with `params`
// (some or all of its parameters; the rest take their defaults), then writes the NaNs of `nan_injections` (those a
// capture recorded for it) as the render did. Timed as a frame on `gpu` times its passes
// (default_pass_timing), so that its time_ms compares with a recorded one.
IsolatedRun run_isolated(GpuDevice& gpu, PipelineCache& cache, const PassDecl& pass,
                         const std::map<std::string, IsolatedInput>& inputs, const ParamValues& params, uint32_t width,
                         uint32_t height, const ShaderProvider& shaders,
                         const std::vector<NanInjection>& nan_injections = {});

}  // namespace nightcap
