// The capture manifest, and what the tools do with a capture before reading any blob. Input: the
// bytes of manifest.json. A manifest that opens must survive, without a crash or a sanitizer
// report, every frame drawn as DOT and a diff of the capture with itself (equal hashes: no blob
// is read), and must write back to JSON that opens to the same JSON: the reader keeps what the
// writer writes.
#include <fstream>

#include "captures/capture.h"
#include "compare/diff.h"
#include "inspect/graph_dot.h"
#include "tests/fuzz/scratch_file.h"

namespace nc = nightcap;

// The harness links no pass, and the passes register the frame's own kinds: it registers their
// names bare (no decoding, drawing or measure), so manifests that name them open and go on to
// the tools instead of stopping at "unknown kind".
static const bool kFrameKindNames = [] {
  for (const char* name : {"normal", "packed_normal", "material", "motion", "depth_stencil", "stencil", "depth_minmax",
                           "light_clusters", "light_depth"})
    nc::register_kind({.kind = nc::ResourceKind(name)});
  return true;
}();

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto folder = nc::fuzz::scratch_folder() / "capture";
  std::filesystem::create_directories(folder);
  nc::fuzz::write_scratch("capture/manifest.json", {data, size});
  std::optional<nc::Capture> capture;
  try {
    capture = nc::Capture::open(folder);
  } catch (const nc::CaptureError&) {
    return 0;
  }
  for (const nc::FrameRecord& frame : capture->manifest().frames) (void)nc::frame_to_dot(frame);
  const nc::CaptureDiff diff = nc::diff_captures(*capture, *capture, {});
  if (!diff.identical || diff.first_divergence) __builtin_trap();
  (void)nc::diff_to_json(diff);

  const nlohmann::json written = nc::to_json(capture->manifest());
  const nlohmann::json again = nc::to_json(nc::manifest_from_json(written, "written manifest"));
  if (written != again) __builtin_trap();
  return 0;
}
