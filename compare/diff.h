// Diff of two captures: passes aligned by name, outputs by resource name, each compared with
// the metric of its kind; the first pass whose outputs differ although its input resources
// agree is where a change entered the frame (the origin: a parameter, a shader, or the pass
// itself), and the passes that differ because what they read differs are inherited.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "captures/capture.h"
#include "compare/metrics.h"
#include "compare/thresholds.h"

namespace nightcap {

struct OutputDiff;

struct DiffOptions {
  // What each output is held to, first that applies: the first rule of `thresholds` matching
  // PASS/RESOURCE; for float outputs, max abs <= `tolerance`; the contract capture A recorded.
  const Thresholds* thresholds = nullptr;
  std::optional<double> tolerance;
  std::optional<uint32_t> frame;  // compare this frame only
  // Capture A is a golden (`nightcap diff --golden`): what one side lacks is named for the side,
  // "output missing" (the golden has it) or "golden missing", instead of "only in A" or "only in B".
  bool golden = false;
  // Called for each output whose versions differ in bytes, once it is measured, with both
  // versions still in memory (so that a report draws them without loading them again). Outputs
  // are measured on a worker per core: it is called from those threads, and must be safe so.
  std::function<void(const FrameRecord& frame_a, const std::string& pass, const OutputDiff& result,
                     const ResourcePair& versions)>
      on_measured;
};

struct OutputDiff {
  std::string resource;
  bool only_in_one = false;
  std::string missing;  // against a golden, the side that lacks it: "output" or "golden"
  ResourceComparison comparison;
  bool beyond = false;                      // outside what it was held to
  std::string held_to;                      // the threshold and where it came from (every output compared)
  ContractCheck contract;                   // when held to the recorded contract
  std::optional<ThresholdCheck> threshold;  // when held to a rule of --thresholds
  // Displayed colour that differs: LDR-FLIP of B against A, with its error map.
  std::optional<FlipResult> flip;
  std::filesystem::path flip_map;  // the error map's picture, where `diff --flip-maps` wrote one
};

enum class PassStatus { identical, origin, inherited, skipped, skipped_in_a, skipped_in_b, only_in_a, only_in_b };
std::string status_name(PassStatus status);
// Against a golden, only_in_a and only_in_b are "output_missing" and "golden_missing".
std::string status_name(PassStatus status, bool golden);

// `diff --isolate`: the pass as capture B recorded it, run on the inputs capture A recorded for
// it (replay/isolate.h).
struct PassIsolation {
  struct Output {
    std::string resource;
    // Made as A recorded it: A's bytes, or within its contract where the output depends on
    // execution order.
    bool reproduced = false;
    std::string made;  // the run's verdict, e.g. "different (float, max abs 2.9)"
  };
  std::string reason;  // why it was not run; empty when it was
  std::vector<Output> outputs;
  // An output the run does not reproduce: the pass itself changed. Otherwise the difference came
  // through its inputs.
  bool pass_changed() const;
};
// One line on what the run found.
std::string isolation_summary(const PassIsolation& isolation);

struct PassDiff {
  std::string name;
  PassStatus status = PassStatus::identical;
  bool inputs_agree = true, params_agree = true, shaders_agree = true;
  std::vector<OutputDiff> outputs;
  bool beyond_tolerance = false;
  std::optional<PassIsolation> isolation;
};

struct FrameDiff {
  uint32_t index = 0;
  // The frame's own inputs that differ (or that one capture lacks): resources that the passes
  // both captures ran read and no pass of the frame writes (the scene's buffers and textures,
  // frame.camera), and history from a frame before that either capture lacks. Where they differ,
  // passes downstream differ with unequal inputs, and none of them need be where the difference
  // started.
  std::vector<std::string> inputs_differ;
  std::vector<PassDiff> passes;
};

struct CaptureDiff {
  std::vector<FrameDiff> frames;
  std::optional<std::pair<uint32_t, std::string>> first_divergence;  // frame, pass
  bool identical = true;
  bool beyond_tolerance = false;
  std::vector<std::string> notes;  // frames present in one capture only, ...
  // The keys of the manifests' "settings" (the command line) and "scene" (its description) whose
  // values differ: what likely made the frames' own inputs differ.
  std::vector<std::string> settings_differ, scene_differ;
  bool golden = false;  // DiffOptions::golden
};

// Throws CaptureError when a blob cannot be read or a capture lacks options.frame.
CaptureDiff diff_captures(const Capture& a, const Capture& b, const DiffOptions& options);
void print_diff_table(std::ostream& out, const CaptureDiff& diff);
// "a, b, c": the inputs and keys that differ, as the table and the JUnit messages name them.
std::string comma_separated(const std::vector<std::string>& names);
// With --isolate's results, "changed_passes" lists the passes found changed themselves.
// "input_divergence" names the first frame whose own inputs differ, and them ({"frame",
// "inputs"}), or is null.
nlohmann::json diff_to_json(const CaptureDiff& diff);

}  // namespace nightcap
