// A capture's pass times in the report: one frame's as a bar chart, every recorded frame's as a
// table.
#pragma once

#include <functional>
#include <string>

#include "captures/capture.h"

namespace nightcap {

// One row per pass that ran, in execution order: a bar for its time (time_ms, by its clock), and
// for a pass timed by the host a thin one for the device's timestamps around it (gpu_ms), which
// on a CPU device absorb other work; on one scale, with the values written beside them. Every
// name is escaped.
std::string timing_chart_svg(const FrameRecord& frame);

// A table of every recorded frame's pass times (time_ms; blank where a pass did not run), a column
// per frame, with each frame's sum and wall clock; "" when one frame is recorded. Pass names link
// to their sections of the report of `shown` (the frame the page is about), anchors given by
// `anchor_of(pass name)`, "" for a pass `shown` does not have (no link).
std::string frame_times_table(const CaptureManifest& manifest, const FrameRecord& shown,
                              const std::function<std::string(const std::string&)>& anchor_of);

// The sum of the times of the passes that ran.
double pass_time_sum(const FrameRecord& frame);

}  // namespace nightcap
