// `nightcap report CAP_A CAP_B -o DIR` (or `--golden NAME --store DIR CAP`): a diff as a static
// HTML folder. At the top, the first divergence and the count of results within and beyond what
// they were held to; then every pass with its status; then, for each output that differs, its
// metrics and the threshold it was held to (and where that came from), and pictures side by side:
// the new version (B) that shows the reference (A) while the pointer is over it, the reference,
// the difference amplified, and FLIP's error map for displayed colour. A click opens a picture
// large, with zoom and the values of the texel under the pointer in both captures.
#pragma once

#include <cstdint>
#include <filesystem>

#include "captures/capture.h"
#include "compare/diff.h"

namespace nightcap {

struct DiffReportOptions {
  uint32_t thumbnail_side = 256;  // the longer side of a thumbnail, pixels
  uint32_t large_side = 512;      // the longer side of the large view (texels taken, not blended)
};

// Diffs `a` (the reference) and `b` with `diff_options` and writes the report into `folder`,
// which must not exist or be empty; index.html last, renamed into place. The pictures are drawn
// as the diff measures each output, from the versions it loaded. Returns the diff. Throws
// CaptureError for what the captures' blobs fail, std::runtime_error for what cannot be written
// (naming the file).
CaptureDiff write_diff_report(const Capture& a, const Capture& b, DiffOptions diff_options,
                              const std::filesystem::path& folder, const DiffReportOptions& options = {});

}  // namespace nightcap
