// `diff` (two captures, or a capture and a golden, pass by pass) and `golden update` and `golden
// list` (the store of goldens a diff compares with).
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>

#include "captures/golden_store.h"
#include "cli/command.h"
#include "cli/diff_flags.h"
#include "compare/diff_results.h"
#include "compare/flip_map.h"
#include "passes/assembly/renderer.h"
#include "replay/isolate.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

void check_golden_name(const std::string& flag, const std::string& name) {
  if (!nc::safe_name(name))
    throw UsageError(flag + " '" + name +
                     "': not a golden name (printable characters, no spaces, '/' or '\\', not . or ..)");
}

}  // namespace

Capture open_golden(const DiffFlags& flags, const std::string& capture) {
  const std::string& name = *flags.golden;
  check_golden_name("--golden", name);
  if (std::filesystem::exists(flags.store)) {
    const nc::GoldenStore store = nc::GoldenStore::open(flags.store);
    if (store.contains(name)) return store.golden(name);
  }
  throw UsageError("golden '" + name + "' missing from store " + flags.store +
                   " (record it with: nightcap golden update " + capture + " --store " + flags.store + " --name " +
                   name + ")");
}

DiffOptions diff_options(const DiffFlags& flags, Thresholds& thresholds) {
  nc::DiffOptions options;
  options.golden = flags.golden.has_value();
  if (!flags.thresholds.empty()) {
    thresholds = nc::read_thresholds(flags.thresholds);
    options.thresholds = &thresholds;
  }
  options.tolerance = flags.tolerance;
  options.frame = flags.frame;
  return options;
}

namespace {

// Exit 0 when every result is within what it was held to, 1 when one is not; the last line
// counts them (on stderr when --json owns stdout). With a golden, `a` is unused: the golden is
// capture A, the reference.
int run_diff(const std::string& a, const std::string& b, const DiffFlags& flags) {
  const auto start = std::chrono::steady_clock::now();
  const nc::Capture capture_a = flags.golden ? open_golden(flags, b) : nc::Capture::open(a);
  const nc::Capture capture_b = nc::Capture::open(b);
  nc::Thresholds thresholds;
  nc::CaptureDiff diff = nc::diff_captures(capture_a, capture_b, diff_options(flags, thresholds));
  if (flags.isolate) {
    nc::GpuDevice gpu({flags.device, validation_requested()});
    nc::isolate_passes(gpu, capture_a, capture_b, diff);
  }
  if (!flags.flip_maps.empty()) nc::write_flip_maps(diff, flags.flip_maps);
  const std::vector<nc::DiffCase> cases = nc::diff_cases(diff);
  const nc::DiffTally counts = nc::tally(cases);
  if (!flags.junit.empty())
    nc::write_junit(flags.junit, cases,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (flags.json)
    std::cout << nc::diff_to_json(diff).dump(1) << "\n";
  else
    nc::print_diff_table(std::cout, diff);
  (flags.json ? std::cerr : std::cout) << counts.passed << " passed, " << counts.failed << " failed\n";
  return counts.failed > 0 ? kExitDifferent : 0;
}

int run_golden_update(const std::string& capture, const std::string& store, const std::string& name) {
  check_golden_name("--name", name);
  const nc::GoldenUpdate update = nc::GoldenStore::update(store, capture, name);
  std::cout << "golden '" << name << "' updated in " << store << " from " << update.golden.source << " ("
            << update.blobs_copied << " blobs copied, " << update.blobs_shared << " already in the store)\n";
  return 0;
}

int run_golden_list(const std::string& store_dir, bool json) {
  const nc::GoldenStore store = nc::GoldenStore::open(store_dir);
  const std::vector<nc::GoldenInfo> goldens = store.list();
  if (json) {
    nlohmann::json out = {{"store", store.root().string()}, {"goldens", nlohmann::json::array()}};
    for (const nc::GoldenInfo& g : goldens)
      out["goldens"].push_back(
          {{"name", g.name}, {"frames", g.frames}, {"passes", g.passes}, {"source", g.source}, {"updated", g.updated}});
    std::cout << out.dump(1) << "\n";
    return 0;
  }
  std::cout << std::left << std::setw(24) << "name" << std::right << std::setw(7) << "frames" << std::setw(8)
            << "passes"
            << "  " << std::left << std::setw(22) << "updated"
            << "source\n";
  for (const nc::GoldenInfo& g : goldens)
    std::cout << std::left << std::setw(24) << g.name << std::right << std::setw(7) << g.frames << std::setw(8)
              << g.passes << "  " << std::left << std::setw(22) << g.updated << g.source << "\n";
  return 0;
}

}  // namespace

Command add_diff_command(CLI::App& app) {
  struct Flags {
    std::string capture, capture_b, golden;
    double tolerance = 0.0;
    uint32_t frame = 0;
    DiffFlags diff;
  };
  auto flags = std::make_shared<Flags>();
  DiffFlags& diff_flags = flags->diff;
  auto* diff = app.add_subcommand(
      "diff",
      "Compare two captures pass by pass and name the first divergent pass: `diff CAP_A CAP_B`, or a capture with a "
      "golden of a store, the reference: `diff --golden NAME --store DIR CAP`.\n"
      "Exit codes: 0 every result within what it was held to, 1 a regression, 2 an error (a missing golden too).");
  auto* capture_a_option =
      diff->add_option("capture_a", flags->capture, "reference capture (with --golden: the capture)");
  auto* capture_b_option = diff->add_option("capture_b", flags->capture_b, "capture to compare");
  auto* golden_option =
      diff->add_option("--golden", flags->golden, "compare the capture with golden NAME of --store (capture A)");
  auto* store_option = diff->add_option("--store", diff_flags.store, "the golden store (`nightcap golden update`)");
  golden_option->needs(store_option);
  store_option->needs(golden_option);
  diff->add_option("--thresholds", diff_flags.thresholds,
                   "JSON rules (glob on PASS/RESOURCE, metric, limit, allowed share, ignored rectangles) that replace "
                   "the recorded contracts of the outputs they match (format: docs/commands/diff.md)");
  auto* tolerance_option = diff->add_option(
      "--tolerance", flags->tolerance,
      "max abs difference accepted for float outputs no --thresholds rule matches, instead of their recorded "
      "contracts (others keep theirs)");
  auto* diff_frame_option = diff->add_option("--frame", flags->frame, "compare frame K only");
  diff->add_option("--junit", diff_flags.junit, "also write JUnit XML: one test case per pass and output");
  diff->add_option("--flip-maps", diff_flags.flip_maps,
                   "write the FLIP error map of each displayed image that differs into DIR as PNG (magma colours)");
  diff->add_flag("--isolate", diff_flags.isolate,
                 "run each differing pass as B recorded it on A's inputs: did the pass change, or its inputs?");
  diff->add_option("--device", diff_flags.device,
                   "Vulkan device of --isolate's runs (name substring); default: lavapipe");
  diff->add_flag("--json", diff_flags.json, "machine-readable output (the last line, the counts, goes to stderr)");
  return {diff, [=] {
            DiffFlags options = flags->diff;
            if (tolerance_option->count()) options.tolerance = flags->tolerance;
            if (diff_frame_option->count()) options.frame = flags->frame;
            // Two captures, or a golden and one capture: never a mixture.
            if (golden_option->count()) {
              options.golden = flags->golden;
              if (capture_b_option->count())
                throw UsageError("--golden compares one capture with the golden: give one capture, not two");
              if (!capture_a_option->count())
                throw UsageError("--golden NAME --store DIR: the capture to compare is missing");
              return run_diff("", flags->capture, options);
            }
            if (!capture_b_option->count())
              throw UsageError("diff needs two captures (CAP_A CAP_B), or --golden NAME --store DIR and one capture");
            return run_diff(flags->capture, flags->capture_b, options);
          }};
}

std::vector<Command> add_golden_commands(CLI::App& app) {
  struct Flags {
    std::string capture, store, name;
    bool json = false;
  };
  auto flags = std::make_shared<Flags>();
  auto* golden = app.add_subcommand("golden", "Keep golden captures in a store: the references of `diff --golden`");
  golden->require_subcommand(1);
  auto* golden_update = golden->add_subcommand(
      "update",
      "Record a capture as golden NAME of a store, replacing an earlier golden of that name (the store is created "
      "when absent; blobs it holds already are not copied again)");
  golden_update->add_option("capture", flags->capture, "capture folder")->required();
  golden_update->add_option("--store", flags->store, "store folder")->required();
  golden_update->add_option("--name", flags->name, "golden name (printable, no spaces, '/' or '\\')")->required();
  auto* golden_list = golden->add_subcommand("list", "List the goldens of a store");
  golden_list->add_option("--store", flags->store, "store folder")->required();
  golden_list->add_flag("--json", flags->json, "machine-readable output");
  return {{golden_update, [flags] { return run_golden_update(flags->capture, flags->store, flags->name); }},
          {golden_list, [flags] { return run_golden_list(flags->store, flags->json); }}};
}
}  // namespace nightcap::cli
