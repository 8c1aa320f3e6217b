// Whether a pass's recorded time is the pass's own: each pass of a capture's frame against the
// same pass replayed alone from its recorded inputs.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/core/isolated.h"
#include "replay/replay.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;
namespace fs = std::filesystem;

namespace nightcap::bench {

namespace {

// A replayed pass is timed this many times after one run that creates its pipelines.
constexpr int kReplays = 3;
// Below this a pass's time is mostly the submit and the fence: not what the figure is about.
constexpr double kLeastMs = 2.0;

}  // namespace

// The city block rendered to a capture of 2 frames, frame 1 recorded (frame 0 compiles the
// pipelines), then each pass of that frame replayed alone from its recorded inputs (once to
// create its pipeline, then kReplays times); `runs` times, so that a run's recording and its
// replays see the same machine. pass_time_agreement: over the passes whose replay takes over
// 2 ms, the largest |recorded − replayed| / replayed, each the median over the runs.
void bench_pass_times(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int runs) {
  nc::Scene scene = nc::build_city(1);
  nc::add_default_lighting(scene);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.frames = 2;
  settings.first_recorded = 1;
  const fs::path dir = fs::temp_directory_path() / "nightcap-bench-pass-times";
  const std::vector<nc::PassDecl> passes = nc::all_passes();
  nc::PipelineCache cache(gpu);
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> recorded, replayed;
  for (int r = 0; r < runs; ++r) {
    fs::remove_all(dir);
    nc::render_to_capture(gpu, scene, settings, dir, false);
    const nc::Capture capture = nc::Capture::open(dir);
    const nc::FrameRecord& frame = capture.manifest().frames.at(0);
    for (const nc::PassRecord& record : frame.passes) {
      const nc::PassDecl* decl = nc::find_pass(passes, record.name);
      if (!record.ran || !decl) continue;
      if (r == 0) order.push_back(record.name);
      recorded[record.name].push_back(record.time_ms);
      const auto inputs = nc::recorded_inputs(capture, record);
      const nc::ParamValues params = nc::resolve_params(*decl, nc::overrides_of(*decl, record.params));
      std::vector<double> times;
      for (int k = 0; k <= kReplays; ++k) {
        const nc::IsolatedRun run =
            nc::run_isolated(gpu, cache, *decl, inputs, params, frame.width, frame.height, nc::builtin_shaders());
        if (k > 0) times.push_back(run.execution.passes.at(0).time_ms);
      }
      replayed[record.name].push_back(median(times));
    }
  }
  fs::remove_all(dir);
  table() << "\n## pass times: recorded in frame 1 of the city block against replayed alone (" << width << "x" << height
          << ", medians of " << runs << " runs, each a capture and " << kReplays
          << " replays of each pass; GPU passes timed " << (gpu.is_cpu() ? "alone by the host" : "by the device")
          << ")\n"
          << std::left << std::setw(22) << "pass" << std::right << std::setw(12) << "recorded" << std::setw(12)
          << "replayed" << std::setw(12) << "rel diff\n";
  double worst = 0.0;
  std::string worst_pass;
  for (const std::string& name : order) {
    const double rec = median(recorded[name]), rep = median(replayed[name]);
    const double diff = rep > 0 ? std::abs(rec - rep) / rep : 0.0;
    const bool counted = rep > kLeastMs;
    table() << std::left << std::setw(22) << name << std::right << std::fixed << std::setprecision(3) << std::setw(12)
            << rec << std::setw(12) << rep << std::setw(11) << std::setprecision(2) << diff
            << (counted ? "" : "  (under 2 ms: not counted)") << "\n";
    figure("pass_time.recorded_ms." + name, rec);
    figure("pass_time.replayed_ms." + name, rep);
    if (counted && diff > worst) {
      worst = diff;
      worst_pass = name;
    }
  }
  table() << "largest relative difference " << std::setprecision(3) << worst << " (" << worst_pass << ")\n";
  figure("pass_time_agreement", worst);
}

}  // namespace nightcap::bench
