// What `diff` and `report` of a diff share: the flags that say what to compare and how, the golden
// a capture is compared with, and the options they make (cli/diff.cpp).
#pragma once

#include <optional>
#include <string>

#include "captures/capture.h"
#include "compare/diff.h"
#include "compare/thresholds.h"

namespace nightcap::cli {

struct DiffFlags {
  std::string thresholds, junit;
  std::optional<double> tolerance;
  std::optional<uint32_t> frame;
  bool json = false;
  bool isolate = false;
  std::string device;  // of --isolate's replays
  std::string flip_maps;
  std::optional<std::string> golden;  // capture A is this golden of `store`
  std::string store;
};

// A golden that is not there is its own result: the first run of a CI job, say, which has to
// record it.
Capture open_golden(const DiffFlags& flags, const std::string& capture);
// What the diff flags ask of diff_captures; `thresholds` keeps the rules of --thresholds.
DiffOptions diff_options(const DiffFlags& flags, Thresholds& thresholds);

}  // namespace nightcap::cli
