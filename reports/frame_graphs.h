// The report's pictures of a frame's graph, laid out by Graphviz: the overview of its passes and
// each pass's own graph, inline in the page so that their nodes link to the passes' sections, and
// the whole graph of every resource version as a file of its own.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

struct FrameGraphs {
  std::string overview;             // <svg> of frame_overview_dot
  std::vector<std::string> passes;  // <svg> of pass_to_dot, one per pass
};

// Writes overview.{dot,svg}, graph.{dot,svg} (frame_to_dot) and graphs/pass-<i>.{dot,svg} in
// `folder` (the pass graphs laid out on every core); nodes link to "#" + `anchor(i)`.
FrameGraphs draw_frame_graphs(const FrameRecord& frame, const std::filesystem::path& folder,
                              const std::function<std::string(size_t)>& anchor);

}  // namespace nightcap
