// Graphviz DOT of one recorded frame: its passes in execution order and every version of every
// resource they read or write, so the data flow of a capture can be looked at (`dot -Tsvg`).
#pragma once

#include <string>

#include "captures/capture.h"

namespace nightcap {

// One node per pass (name, status, its time and clock; skipped and culled ones dashed and grey with
// their reason) and one per resource version (name, format and size or buffer bytes, content
// hash), with edges writer → version → readers. A history input (previous(name)) is a blue
// dashed node saying whether it came from the previous frame or is the initial value (and why),
// and the final version of that resource has a blue edge to the next frame's history. Every text
// taken from the record is escaped, so any name or reason gives valid DOT.
std::string frame_to_dot(const FrameRecord& frame);

}  // namespace nightcap
