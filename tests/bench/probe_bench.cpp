// The reflection probes: what they cost in the street frame, what one probe's update costs, and
// time against error for the prefilter's samples and the probes captured per frame.
#include <iomanip>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/probe_capture.h"

namespace nc = nightcap;

namespace nightcap::bench {
namespace {

// The capture's passes, whose times add up to the probes' updates of a frame (probes.keep, which
// carries the array over every frame, is not an update).
const char* const kUpdatePasses[] = {"probes.plan", "probes.cull", "probes.gbuffer", "probes.light", "probes.convert"};

double update_ms(const nc::RenderedFrame& frame) {
  double sum = 0;
  for (const char* pass : kUpdatePasses) sum += frame_pass_ms(frame, pass);
  return sum;
}

nc::ProbePlan plan_of(const nc::RenderedFrame& frame) {
  const VersionData* record = frame.execution.final_version("probes.plan");
  return nc::read_probe_plan(record && record->bytes ? std::span<const uint8_t>(*record->bytes)
                                                     : std::span<const uint8_t>());
}

}  // namespace

// Probes on against off (`--set probes.enabled=0`: reflections of the sky alone) in the frame
// frame_ms_street measures, the map's street shot walking: two renderers warmed up by frame 0
// (the reset, which captures every probe in range), then frames 1..repeats on each in turn; the
// ratio of the medians of the whole frame's wall clock (probes_on_off_ratio). Then one probe's
// update (probe_update_ms): with `refresh_frames` 1 and a budget of 1, every frame captures the
// stalest probe again; the median over frames of the capture's passes timed alone.
void bench_probes(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## reflection probes, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  nc::RenderSettings on;
  on.width = width;
  on.height = height;
  on.pass_timing = nc::PassTiming::overlapped;
  nc::RenderSettings off = on;
  off.params["probes"]["enabled"] = 0.0;
  {
    nc::Renderer with(gpu, scene, on), without(gpu, scene, off);
    with.render_frame(0, false);
    without.render_frame(0, false);
    std::vector<double> on_ms, off_ms;
    for (int r = 1; r <= repeats; ++r)
      for (const bool probes : {r % 2 == 1, r % 2 == 0}) {
        const double start = now_ms();
        (probes ? with : without).render_frame(uint32_t(r), false);
        (probes ? on_ms : off_ms).push_back(now_ms() - start);
      }
    const double ratio = median(on_ms) / median(off_ms);
    table() << "on " << std::fixed << std::setprecision(1) << median(on_ms) << " ms, off " << median(off_ms)
            << " ms, ratio " << std::setprecision(3) << ratio << "\n";
    figure("probes_on_off_ratio", ratio);
    figure("frame_ms_street_probes_on", median(on_ms));
    figure("frame_ms_street_probes_off", median(off_ms));
  }
  nc::RenderSettings one = on;
  one.pass_timing.reset();  // each pass timed alone on a CPU device
  one.params["probes.plan"]["refresh_frames"] = 1.0;
  one.params["probes.plan"]["max_updates"] = 1.0;
  nc::Renderer renderer(gpu, scene, one);
  renderer.render_frame(0, false);
  std::vector<double> update;
  for (int r = 1; r <= repeats; ++r) {
    const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
    if (plan_of(frame).captured == 1) update.push_back(update_ms(frame));
  }
  table() << "one probe's update (plan, cull, G-buffer, light, convert): " << std::setprecision(1) << median(update)
          << " ms\n";
  figure("probe_update_ms", median(update));
}

// Time against error. Prefilter samples: probes.convert alone on a synthetic capture (64 texels
// a face, tests/reference/probe_capture.h) against GGX's prefilter converged in double (32768
// samples), RMSE over 128 texels of each prefiltered mip relative to the reference's RMS, the
// worst mip; time: the pass's, as the frame times it (alone, by the host's clock, on a CPU device). Probes captured per
// frame (max_updates): the street shot driving, a frame every second (14 m apart, so probes come in range), each
// frame's capture passes timed alone (their mean over the frames) against the share of the probes in range still
// waiting for a capture (their reflections show the sky), over 12 frames after the reset.
void bench_probe_tradeoffs(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  table() << "\n## probes.convert: prefilter samples against error (synthetic capture, 64 texels a face)\n"
          << "samples at mip 1   ms   worst mip RMSE\n";
  const reference::ProbeCapture capture = reference::synthetic_capture(64);
  const uint32_t array_side = 256, slot = 0;
  for (const uint32_t samples : {16u, 32u, 64u, 128u, 255u}) {
    const nc::IsolatedRun run = nc::run_isolated(gpu, cache, nc::probes_convert_pass(),
                                                 reference::convert_inputs(capture, slot, array_side, glm::dvec3(0.0)),
                                                 {{"samples", double(samples)}}, 1, 1, nc::builtin_shaders());
    const std::vector<uint8_t>& array = *run.outputs.at("probes.array");
    const ImageExtent extent{array_side, array_side, 1, kProbeArrayMips, 2 * kProbeSlots};
    double worst = 0;
    for (uint32_t mip = 1; mip < kProbeArrayMips; ++mip) {
      const uint32_t side = mip_size(array_side, mip);
      const double roughness = double(mip) / (kProbeArrayMips - 1);
      double squares = 0, signal = 0;
      for (uint32_t k = 0; k < 128; ++k) {
        const uint32_t h = k % 2, x = (k * 37 + mip) % side, y = (k * 53 + 3 * mip) % side;
        const glm::dvec3 d =
            paraboloid_direction(h, glm::dvec2((x + 0.5) / side * 2.0 - 1.0, (y + 0.5) / side * 2.0 - 1.0));
        const glm::dvec3 expected = reference::prefiltered(capture.level0, d, roughness, 32768);
        const glm::dvec3 got = reference::half4_at(
            array, raw_subresource_offset(*format_info(reference::kHalf4), extent, 0, mip, 2 * slot + h) +
                       (uint64_t(y) * side + x) * 8);
        squares += glm::dot(got - expected, got - expected);
        signal += glm::dot(expected, expected);
      }
      worst = std::max(worst, std::sqrt(squares / signal));
    }
    table() << std::setw(17) << samples << std::setw(9) << std::fixed << std::setprecision(2)
            << run.execution.passes.at(0).time_ms << std::setw(17) << std::setprecision(4) << worst
            << (samples == 64 ? "   (default)" : "") << "\n";
    figure("probe_prefilter_ms." + std::to_string(samples), run.execution.passes.at(0).time_ms);
    figure("probe_prefilter_rmse." + std::to_string(samples), worst);
  }

  table() << "\n## probes captured per frame: street shot driving, a frame a second, 12 frames after the reset\n"
          << "max_updates   capture ms/frame (mean)   probes waiting\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  for (const uint32_t budget : {1u, 2u, 4u, 8u}) {
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = nc::CameraPath::Motion::drive;
    settings.params["probes.plan"]["max_updates"] = double(budget);
    nc::Renderer renderer(gpu, scene, settings);
    renderer.render_frame(0, false);
    std::vector<double> ms;
    double waiting = 0, in_range = 0;
    for (uint32_t k = 1; k <= 12; ++k) {
      const nc::RenderedFrame frame = renderer.render_frame(60 * k, false);
      ms.push_back(update_ms(frame));
      const nc::ProbePlan plan = plan_of(frame);
      for (uint32_t s = 0; s < kProbeSlots; ++s) {
        in_range += plan.slot_probe[s] != kNoProbe;
        waiting += plan.slot_state[s] == uint32_t(nc::ProbeSlotState::waiting);
      }
    }
    const double share = in_range > 0 ? waiting / in_range : 0.0;
    double mean = 0;
    for (double m : ms) mean += m / double(ms.size());
    table() << std::setw(11) << budget << std::setw(26) << std::fixed << std::setprecision(1) << mean << std::setw(17)
            << std::setprecision(3) << share << (budget == 2 ? "   (default)" : "") << "\n";
    figure("probe_budget_ms." + std::to_string(budget), mean);
    figure("probe_budget_waiting." + std::to_string(budget), share);
  }
}

}  // namespace nightcap::bench
