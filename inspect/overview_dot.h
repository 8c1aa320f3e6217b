// Graphviz DOT of a recorded frame at the level of passes, for a frame of 60 passes to read at a
// glance: the overview (every pass, grouped by stage, linked to what it feeds) and each pass's own
// graph (what it read and wrote, and from and for whom). frame_to_dot (graph_dot.h) keeps every
// version of every resource.
#pragma once

#include <functional>
#include <string>

#include "captures/capture.h"

namespace nightcap {

// Where a node links: the URL of pass `index`'s section, "" for none.
using PassLink = std::function<std::string(size_t index)>;

// One node per pass (name and time; skipped ones dashed, with their reason as a tooltip), in a
// cluster per stage (PassRecord::stage, in frame order; passes without one outside any), and an
// edge from each pass to each later pass that reads what it wrote, the resources its tooltip.
// What no pass of the frame wrote (scene data, the camera, the previous frame's history) draws
// no edge: each pass's own graph shows it. Every text from the record is escaped.
std::string frame_overview_dot(const FrameRecord& frame, const PassLink& link);

// Pass `index` between its inputs and outputs: each input labelled with the pass that wrote it
// (or "scene, camera" when none did, or the history it is), each output with the passes that
// read it; resources link to the section of that writer or first reader.
std::string pass_to_dot(const FrameRecord& frame, size_t index, const PassLink& link);

}  // namespace nightcap
