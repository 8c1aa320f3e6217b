// `passes`, `check` and `graph`: a capture's passes listed, every blob of it checked, and a
// frame's render graph drawn.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "captures/capture.h"
#include "cli/command.h"
#include "inspect/capture_check.h"
#include "inspect/graph_dot.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

int run_passes(const std::string& path, bool json) {
  const nc::Capture capture = nc::Capture::open(path);
  if (json) {
    const nlohmann::json out = {{"frames", nc::to_json(capture.manifest()).at("frames")}};
    std::cout << out.dump(1) << "\n";
    return 0;
  }
  for (const nc::FrameRecord& frame : capture.manifest().frames) {
    std::cout << "frame " << frame.index << " at " << std::fixed << std::setprecision(3) << frame.time << " s"
              << (frame.wall_ms ? ", " + ms(frame.wall_ms) + " ms wall clock" : "")
              << (frame.camera_cut ? ", camera cut" : "");
    for (const auto& [resource, reason] : frame.history_reset)
      std::cout << "; history of " << resource << " restarted (" << reason << ")";
    std::cout << "\n";
    // `ms` is the pass's time by its `clock` (docs/commands/passes.md); `gpu ms` the device's
    // timestamps, as recorded whatever the clock.
    size_t name_width = 20;
    for (const nc::PassRecord& p : frame.passes) name_width = std::max(name_width, p.name.size() + 1);
    std::cout << std::left << std::setw(int(name_width + 2)) << "  pass" << std::setw(9) << "status" << std::right
              << std::setw(10) << "ms"
              << "  " << std::left << std::setw(11) << "clock" << std::right << std::setw(10) << "gpu ms"
              << "  outputs\n";
    for (const nc::PassRecord& p : frame.passes) {
      std::cout << "  " << std::left << std::setw(int(name_width)) << p.name << std::setw(9)
                << (p.ran ? "ran" : "skipped") << std::right << std::setw(10) << (p.ran ? ms(p.time_ms) : "-") << "  "
                << std::left << std::setw(11) << (p.ran ? nc::pass_clock_name(p.clock) : "") << std::right
                << std::setw(10) << ms(p.gpu_ms) << "  ";
      if (!p.ran) std::cout << "(" << p.reason << ") ";
      for (const nc::ResourceRecord& o : p.outputs) {
        std::cout << o.resource << " ";
        if (o.is_buffer)
          std::cout << "[" << o.buffer_size << " B] ";
        else
          std::cout << "[" << nc::format_info(o.format)->name << " " << o.extent.width << "x" << o.extent.height
                    << (o.extent.mips > 1 ? " mips " + std::to_string(o.extent.mips) : "") << "] ";
      }
      std::cout << "\n";
    }
  }
  return 0;
}

// Exit 0 when every blob the manifest names reads, decodes and matches its hash; 2 when any does
// not, as for a manifest that cannot be read.
int run_check(const std::string& path, bool json) {
  const auto start = std::chrono::steady_clock::now();
  const nc::Capture capture = nc::Capture::open(path);
  const nc::CaptureCheck check = nc::check_capture(capture);
  if (json) {
    nlohmann::json out = nc::to_json(check);
    out["capture"] = path;
    std::cout << out.dump(1) << "\n";
    return check.bad.empty() ? 0 : kExitBadInput;
  }
  constexpr size_t kReferencesShown = 3;
  for (const nc::BadBlob& bad : check.bad) {
    std::cout << bad.blob << ": " << nc::blob_problem_name(bad.check.problem) << "\n  " << bad.check.detail << "\n";
    for (size_t i = 0; i < std::min(bad.references.size(), kReferencesShown); ++i)
      std::cout << "  " << nc::describe(bad.references[i]) << "\n";
    if (bad.references.size() > kReferencesShown)
      std::cout << "  and " << bad.references.size() - kReferencesShown << " more\n";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "checked " << check.blobs << " blobs (" << std::fixed << std::setprecision(1)
            << check.bytes_on_disk / 1048576.0 << " MiB) in " << std::setprecision(2) << seconds << " s: ";
  if (check.bad.empty())
    std::cout << "every blob reads, decodes and matches its hash\n";
  else
    std::cout << check.bad.size() << " bad\n";
  return check.bad.empty() ? 0 : kExitBadInput;
}

int run_graph(const std::string& path, uint32_t frame, const std::string& output) {
  const nc::Capture capture = nc::Capture::open(path);
  const nc::FrameRecord* record = nullptr;
  try {
    record = &capture.frame(frame);
  } catch (const nc::CaptureError& e) {
    throw UsageError("--frame " + std::to_string(frame) + ": " + e.what());
  }
  const std::string dot = nc::frame_to_dot(*record);
  if (output.empty()) {
    std::cout << dot;
    return 0;
  }
  std::ofstream file(output, std::ios::binary | std::ios::trunc);
  file << dot;
  file.close();
  if (!file) throw UsageError(output + ": cannot write");
  return 0;
}

}  // namespace

Command add_passes_command(CLI::App& app) {
  struct Flags {
    std::string capture;
    bool json = false;
  };
  auto flags = std::make_shared<Flags>();
  auto* passes = app.add_subcommand("passes", "List the passes of a capture");
  passes->add_option("capture", flags->capture, "capture folder")->required();
  passes->add_flag("--json", flags->json, "machine-readable output");
  return {passes, [flags] { return run_passes(flags->capture, flags->json); }};
}

Command add_check_command(CLI::App& app) {
  struct Flags {
    std::string capture;
    bool json = false;
  };
  auto flags = std::make_shared<Flags>();
  auto* check = app.add_subcommand(
      "check",
      "Read every blob of a capture, decode it and check its content hash (other commands read only the blobs they "
      "need): name each bad blob, what is wrong (missing, refused, truncated, undecodable, hash_mismatch) and the "
      "records that refer to it.\nExit codes: 0 every blob is sound, 2 a bad blob or an unreadable manifest.");
  check->add_option("capture", flags->capture, "capture folder")->required();
  check->add_flag("--json", flags->json, "machine-readable output");
  return {check, [flags] { return run_check(flags->capture, flags->json); }};
}

Command add_graph_command(CLI::App& app) {
  struct Flags {
    std::string capture, output;
    uint32_t frame = 0;
    bool dot = false;
  };
  auto flags = std::make_shared<Flags>();
  auto* graph = app.add_subcommand("graph", "Draw one frame's render graph: passes and resource versions");
  graph->add_option("capture", flags->capture, "capture folder")->required();
  graph->add_option("--frame", flags->frame, "frame index")->capture_default_str();
  // DOT is the only format so far; required so that a later one (--json) can stand beside it.
  graph->add_flag("--dot", flags->dot, "write Graphviz DOT (render it with e.g. `dot -Tsvg`)")->required();
  graph->add_option("-o,--output", flags->output, "file to write (default: standard output)");
  return {graph, [flags] { return run_graph(flags->capture, flags->frame, flags->output); }};
}
}  // namespace nightcap::cli
