// A frame's pass timings as an inline SVG bar chart.
#pragma once

#include <string>

#include "captures/capture.h"

namespace nightcap {

// One row per pass that ran, in execution order: a bar for its GPU time (the timestamp queries
// around its commands) and a thinner one for the CPU time of recording it, on one scale, with
// the values written beside them. Every name is escaped.
std::string timing_chart_svg(const FrameRecord& frame);

}  // namespace nightcap
