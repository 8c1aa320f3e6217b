// `report`: a capture, or the diff of two, as a static HTML report.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/command.h"
#include "cli/diff_flags.h"
#include "reports/capture_report.h"
#include "reports/diff_report.h"
#include "reports/html.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

// A folder `report --force` may replace: empty, or holding a report nightcap wrote (its
// index.html says so), never any other folder.
bool replaceable_report(const std::filesystem::path& folder) {
  if (std::filesystem::is_empty(folder)) return true;
  std::ifstream index(folder / "index.html");
  std::string head(512, '\0');
  index.read(head.data(), std::streamsize(head.size()));
  return head.find(nc::kReportGenerator) != std::string::npos;
}

// Empties `output` for a report: it must not exist or be empty, or with --force hold a report.
void prepare_report_folder(const std::string& output, bool force) {
  const std::filesystem::path folder(output);
  if (!std::filesystem::exists(folder) || std::filesystem::is_empty(folder)) return;
  if (!force) throw UsageError(output + ": exists and is not empty (--force replaces an earlier report)");
  if (!replaceable_report(folder))
    throw UsageError(output + ": --force replaces only a folder holding a nightcap report, and this is not one");
  std::filesystem::remove_all(folder);
}

// One capture: its report. Two (or a golden and one): the report of their diff, with the diff's
// flags; it exits 0 once written, whatever the diff found (`diff` is the command that gates).
int run_report(const std::string& a, const std::string& b, const DiffFlags& flags, const std::string& output,
               bool force) {
  const bool of_diff = flags.golden || !b.empty();
  const nc::Capture capture = flags.golden ? open_golden(flags, a) : nc::Capture::open(a);
  if (flags.frame) {
    try {
      capture.frame(*flags.frame);
    } catch (const nc::CaptureError& e) {
      throw UsageError("--frame " + std::to_string(*flags.frame) + ": " + e.what());
    }
  }
  if (!of_diff && (!flags.thresholds.empty() || flags.tolerance))
    throw UsageError("--thresholds and --tolerance apply to the report of a diff: give two captures");
  // With a golden, the golden is A and the one capture given is B. Everything is opened before an
  // earlier report is replaced.
  const std::optional<nc::Capture> capture_b =
      of_diff ? std::optional(nc::Capture::open(flags.golden ? a : b)) : std::nullopt;
  nc::Thresholds thresholds;
  const nc::DiffOptions options = diff_options(flags, thresholds);
  prepare_report_folder(output, force);
  try {
    if (capture_b)
      nc::write_diff_report(capture, *capture_b, options, output);
    else
      nc::write_capture_report(capture, output, {.frame = flags.frame});
  } catch (...) {
    // The folder was empty: what is in it is this run's, and a report cut short leaves nothing.
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator(output, ignored))
      std::filesystem::remove_all(entry.path(), ignored);
    throw;
  }
  std::cout << "report: " << (std::filesystem::path(output) / "index.html").string() << "\n";
  return 0;
}

}  // namespace

Command add_report_command(CLI::App& app) {
  struct Flags {
    std::string capture, capture_b, output;
    uint32_t frame = 0;
    bool force = false;
    double tolerance = 0.0;
    DiffFlags diff;
  };
  auto flags = std::make_shared<Flags>();
  DiffFlags& report_flags = flags->diff;
  auto* report = app.add_subcommand(
      "report", "Write a capture, or the diff of two, as a static HTML report (opens from disk, no server needed)");
  report->add_option("capture", flags->capture, "capture folder (of a diff: the reference, A)")->required();
  report->add_option("capture_b", flags->capture_b, "the new capture (B): write the report of the diff of A and B");
  report->add_option("-o,--output", flags->output, "folder to write (must not exist, or be empty)")->required();
  auto* report_frame_option = report->add_option(
      "--frame", flags->frame, "frame to show (default: the first the capture recorded; of a diff: every frame)");
  report->add_flag("--force", flags->force, "replace an earlier report in the output folder");
  auto* report_golden = report->add_option("--golden", report_flags.golden,
                                           "the diff of CAPTURE against this golden of --store (the golden is A)");
  report->add_option("--store", report_flags.store, "store of goldens (with --golden)");
  report->add_option("--thresholds", report_flags.thresholds, "of a diff: threshold rules, as `diff --thresholds`");
  auto* report_tolerance_option = report->add_option("--tolerance", flags->tolerance,
                                                     "of a diff: max abs for float outputs, as `diff --tolerance`");
  return {report, [=] {
            DiffFlags options = flags->diff;
            if (report_frame_option->count()) options.frame = flags->frame;
            if (report_tolerance_option->count()) options.tolerance = flags->tolerance;
            if (report_golden->count() && !flags->capture_b.empty())
              throw UsageError("--golden compares one capture with the golden: give one capture, not two");
            if (report_golden->count() && options.store.empty()) throw UsageError("--golden needs --store DIR");
            return run_report(flags->capture, flags->capture_b, options, flags->output, flags->force);
          }};
}
}  // namespace nightcap::cli
