// Runs a compiled graph on a device: CPU passes first (they read only host data), then every
// GPU pass recorded into one command buffer with the barriers the graph derives, a
// debug label and timestamps around each, and — when capturing — a readback of every version
// of every resource a pass wrote or read from the history pool.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "passes/core/context.h"
#include "passes/core/graph.h"

namespace nightcap {

class HistoryPool;

// What is read back to the host is the graph's (GraphSettings::capture and readback).
struct ExecutionOptions {
  std::map<std::string, ParamValues> params;  // per pass; missing ones take their defaults
  ShaderProvider shaders;
  std::string name;  // of the command buffer, for debuggers; empty: "frame <graph frame index>"
  // Where previous(name) inputs that are not imported come from, and where this frame's values
  // go (passes/core/history.h). Kept by the caller across frames.
  HistoryPool* history = nullptr;
};

struct VersionData {
  std::string resource;
  ResourceDesc desc;
  std::shared_ptr<const std::vector<uint8_t>> bytes;  // null when not read back
};

struct PassExecution {
  std::vector<int> inputs, outputs;  // indices into Execution::versions
  std::optional<double> gpu_ms;
  double cpu_ms = 0.0;
  std::map<std::string, std::vector<uint32_t>> spirv;  // path -> code the pass ran
  nlohmann::json pipelines = nlohmann::json::array();  // describe() of each pipeline it bound
  nlohmann::json samplers = nlohmann::json::array();   // and of each distinct sampler it used
};

struct Execution {
  std::vector<VersionData> versions;
  std::vector<PassExecution> passes;  // parallel to CompiledGraph::passes
  // Histories that started from their initial value this frame, and why ("first frame",
  // "camera cut", "size changed").
  std::map<std::string, std::string> history_reset;
  const VersionData* final_version(const std::string& resource) const;
};

Execution execute_graph(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph,
                        const std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>& imports,
                        const ExecutionOptions& options);

}  // namespace nightcap
