// Replay: re-executes passes of a capture from their recorded inputs through the same pass
// code the renderer runs, and compares what they produce with what was recorded.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "captures/capture.h"
#include "compare/metrics.h"
#include "passes/core/device.h"
#include "passes/core/isolated.h"
#include "passes/core/pass.h"

namespace nightcap {

struct ReplayOptions {
  uint32_t frame = 0;
  std::vector<std::string> passes;                  // empty: every pass that ran
  ParamOverrides params;                            // overrides of recorded parameters (--set)
  std::map<std::string, std::string> shader_files;  // pass -> GLSL file replacing its shader of that stage
  bool chain = false;  // feed replayed outputs to later passes instead of the recorded ones
};

enum class Verdict { identical, within_tolerance, different };
std::string verdict_name(Verdict verdict);

struct OutputCheck {
  std::string resource;
  Verdict verdict = Verdict::identical;
  std::string metric;            // how "different" / "within tolerance" was measured
  double amount = 0.0;           // max abs difference
  std::string first_difference;  // buffers with a schema: the first differing element and field
  // Where the bytes differ but the shapes agree: how far the replay is from the recorded output
  // in the terms of its recorded contract (an override is judged by it, a verify only for
  // order-dependent outputs).
  std::optional<ContractCheck> contract;
  std::string recorded_hash, replayed_hash;
};

struct PassReplay {
  std::string name;
  bool replayed = false;
  std::string reason;  // why not replayed
  std::optional<double> gpu_ms;
  double cpu_ms = 0.0;
  double time_ms = 0.0;  // PassExecution::time_ms of the replay, by `clock`
  PassClock clock = PassClock::host;
  std::vector<OutputCheck> outputs;
  std::vector<std::string> notes;  // e.g. shader overridden
};

struct ReplayReport {
  uint32_t frame = 0;
  std::string device;
  std::vector<PassReplay> passes;
  bool any_different() const;
};

// The recorded inputs of `pass`, as run_isolated takes them. A version whose recorded hash is
// in `substitutes` takes those bytes instead of the capture's (a chained replay).
using BytesByHash = std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>;
std::map<std::string, IsolatedInput> recorded_inputs(const Capture& capture, const PassRecord& pass,
                                                     const BytesByHash& substitutes = {});

// Throws CaptureError for an unreadable capture, SceneError for bad options (unknown pass,
// parameter, shader file), ShaderError for a shader that does not compile.
ReplayReport replay_capture(GpuDevice& gpu, const Capture& capture, const ReplayOptions& options);

// `diff --isolate`: runs `pass` of frame `frame` as capture `b` recorded it (its SPIR-V, parameters
// and injected NaN) on the inputs capture `a` recorded for it, and checks what it makes against
// a's outputs as replay_capture checks a replay. Outputs a reproduces say the difference came
// through the pass's inputs; outputs it does not, that the pass itself changed. Throws as
// replay_capture does.
PassReplay replay_across(GpuDevice& gpu, const Capture& a, const Capture& b, uint32_t frame, const std::string& pass);

}  // namespace nightcap
