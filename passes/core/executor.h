// Runs a compiled graph on a device, pass by pass in its order: GPU passes are recorded with
// the barriers the graph planned, a debug label and timestamps around each, and — when
// capturing — a readback of every version of every resource a pass wrote or read from the
// history pool; a CPU pass runs on the host while the frame is recorded, and where it reads
// what GPU passes computed, the frame so far is submitted and waited for first (one more
// submit). Transient resources share memory where their lifetimes allow (FrameMemory).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "passes/core/context.h"
#include "passes/core/graph.h"
#include "passes/core/pass_time.h"

namespace nightcap {

class HistoryPool;

// What is read back to the host is the graph's (GraphSettings::capture and readback).
struct VersionData;

struct ExecutionOptions {
  ShaderProvider shaders;
  std::string name;  // of the command buffer, for debuggers; empty: "frame <graph frame index>"
  // Where previous(name) inputs that are not imported come from, and where this frame's values
  // go (passes/core/history.h). Kept by the caller across frames.
  HistoryPool* history = nullptr;
  // Transient resources alive at different steps share memory; false gives each its own (the
  // results must not change).
  bool alias_memory = true;
  // Called on this thread with each version as soon as its bytes reach the host, while later
  // passes may still run: a capture writer starts encoding it there. When set (and the graph
  // reads back), the frame is submitted in parts, one after each pass whose outputs are read
  // back, with one part in flight while the next is recorded. With PassTiming::alone it is
  // called once the frame has run, so that no encoding runs beside a timed pass.
  std::function<void(const VersionData&)> on_read_back;
  // How each pass's time_ms is measured (passes/core/pass_time.h). `alone` submits every GPU
  // pass that runs by itself, once what came before it has finished: slower, for pass times.
  PassTiming pass_timing = PassTiming::overlapped;
  // With PassTiming::alone: the host's caches are flushed before each timed pass
  // (flush_host_caches), as replay does on a CPU device to time a pass as the frame found it.
  bool cold_caches = false;
};

struct VersionData {
  std::string resource;
  ResourceDesc desc;
  std::shared_ptr<const std::vector<uint8_t>> bytes;  // null when not read back
};

struct PassExecution {
  std::vector<int> inputs, outputs;  // indices into Execution::versions
  std::optional<double> gpu_ms;      // the device's timestamps, for a GPU pass that ran
  double cpu_ms = 0.0;               // a CPU pass's run on the host
  // Its time as ExecutionOptions::pass_timing measures it: gpu_ms (PassClock::device) when
  // overlapped, the host's clock around its own submit (host_alone) when alone; cpu_ms (host)
  // for a CPU pass.
  double time_ms = 0.0;
  PassClock clock = PassClock::host;
  // A GPU pass: the host's time recording its commands, which includes creating each pipeline
  // the first time it is bound (on lavapipe, compiling its shaders: most of a first frame).
  double record_ms = 0.0;
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
  // Device memory of the frame's resources (transient ones and history slots), as allocated and
  // as it would be with every transient resource in memory of its own.
  uint64_t memory_bytes = 0, memory_bytes_without_aliasing = 0;
  uint32_t submits = 0;  // command buffers the frame ran as (a CPU pass reading GPU results splits it)
  // The host's wall clock from the frame's first command to its last result, without the
  // on_read_back calls that PassTiming::alone holds until the end.
  double wall_ms = 0.0;
  const VersionData* final_version(const std::string& resource) const;
};

Execution execute_graph(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph,
                        const std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>& imports,
                        const ExecutionOptions& options);

}  // namespace nightcap
