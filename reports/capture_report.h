// `nightcap report CAP -o DIR`: a capture as a static HTML folder that opens from file:// with no
// server or network. index.html shows one frame: the capture's scene and device, the pass graph
// laid out by Graphviz, the pass timings as a chart, the skipped and culled passes with their
// reasons, and each pass in execution order with thumbnails of its inputs and outputs (the
// debugger's visualisation per kind of data), its parameters, pipeline and sampler state and
// the GLSL of its shaders. Every text taken from the capture is escaped; every file the report
// writes has a name the report makes up, inside DIR.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

#include "captures/capture.h"

namespace nightcap {

struct CaptureReportOptions {
  std::optional<uint32_t> frame;  // default: the first frame the capture recorded
  uint32_t thumbnail_side = 256;  // the longer side of a thumbnail, pixels
};

// Writes the report into `folder`, which must not exist or be empty: images/, graph.dot,
// graph.svg, report.css, then index.html, renamed into place last, so a report cut short has no
// index.html. Throws CaptureError for what the capture's blobs fail, std::runtime_error for
// what cannot be written (naming the file).
void write_capture_report(const Capture& capture, const std::filesystem::path& folder,
                          const CaptureReportOptions& options = {});

}  // namespace nightcap
