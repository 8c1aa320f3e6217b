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
  street_on_off(gpu, scene, width, height, repeats, "probes", "probes_on_off_ratio", "probes");
  nc::RenderSettings one;  // each pass timed alone on a CPU device
  one.width = width;
  one.height = height;
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
// worst mip; time: the pass's, as the frame times it (alone, by the host's clock, on a CPU
// device). Then face resolution and probes captured per frame, in the map's street shot, each
// frame's capture passes timed alone.
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

  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  nc::RenderSettings still;
  still.width = width;
  still.height = height;
  still.path.motion = nc::CameraPath::Motion::still;
  still.pass_timing.reset();  // each pass timed alone on a CPU device

  // Face resolution: the reset frame of the still street shot (every probe in range captured) at
  // each face_size; time: its capture passes per probe captured; error: lighting.lit against the
  // finest setting's, RMS over the frame relative to the RMS of what the probes add to it (the
  // finest setting's lighting.lit less that of probes off), so 1 would be as wrong as no probes.
  table() << "\n## probe face resolution: street shot at " << width << "x" << height
          << ", the reset frame\nface_size   ms/probe   lighting.lit error (share of the probes' contribution)\n";
  const auto lit = [&](const nc::RenderSettings& settings, double* ms_per_probe) {
    nc::Renderer renderer(gpu, scene, settings);
    const nc::RenderedFrame frame = renderer.render_frame(0, true);
    if (ms_per_probe) *ms_per_probe = update_ms(frame) / std::max(1u, plan_of(frame).captured);
    return *frame.execution.final_version("lighting.lit")->bytes;
  };
  nc::RenderSettings off = still;
  off.params["probes"]["enabled"] = 0.0;
  const std::vector<uint8_t> without = lit(off, nullptr);
  const std::vector<uint32_t> face_sizes = {16, 32, 64, 128, 256};
  std::vector<std::vector<uint8_t>> images;
  std::vector<double> ms(face_sizes.size());
  for (size_t k = 0; k < face_sizes.size(); ++k) {
    nc::RenderSettings settings = still;
    settings.params["probes"]["face_size"] = double(face_sizes[k]);
    images.push_back(lit(settings, &ms[k]));
  }
  const uint64_t texels = uint64_t(width) * height;
  const double contribution = rgba16f_rms_difference(images.back(), without, texels);
  for (size_t k = 0; k < face_sizes.size(); ++k) {
    const double error = rgba16f_rms_difference(images[k], images.back(), texels) / std::max(contribution, 1e-30);
    table() << std::setw(9) << face_sizes[k] << std::setw(11) << std::fixed << std::setprecision(1) << ms[k]
            << std::setw(12) << std::setprecision(4) << error << (face_sizes[k] == 64 ? "   (default)" : "")
            << (k + 1 == face_sizes.size() ? "   (the reference)" : "") << "\n";
    figure("probe_face_ms." + std::to_string(face_sizes[k]), ms[k]);
    figure("probe_face_error." + std::to_string(face_sizes[k]), error);
  }

  // Probes captured per frame: the street shot driving, 84 m between frames (a frame every 6 s),
  // so that several probes (one a 100 m block) come in range each frame.
  table() << "\n## probes captured per frame: street shot driving, a frame every 6 s, 12 frames after the reset\n"
          << "max_updates   capture ms/frame (mean)   probes waiting\n";
  for (const uint32_t budget : {1u, 2u, 4u, 8u}) {
    nc::RenderSettings settings = still;
    settings.path.motion = nc::CameraPath::Motion::drive;
    settings.params["probes.plan"]["max_updates"] = double(budget);
    nc::Renderer renderer(gpu, scene, settings);
    renderer.render_frame(0, false);
    std::vector<double> frame_ms;
    double waiting = 0, in_range = 0;
    for (uint32_t k = 1; k <= 12; ++k) {
      const nc::RenderedFrame frame = renderer.render_frame(360 * k, false);
      frame_ms.push_back(update_ms(frame));
      const nc::ProbePlan plan = plan_of(frame);
      for (uint32_t s = 0; s < kProbeSlots; ++s) {
        in_range += plan.slot_probe[s] != kNoProbe;
        waiting += plan.slot_state[s] == uint32_t(nc::ProbeSlotState::waiting);
      }
    }
    const double share = in_range > 0 ? waiting / in_range : 0.0;
    double mean = 0;
    for (double m : frame_ms) mean += m / double(frame_ms.size());
    table() << std::setw(11) << budget << std::setw(26) << std::fixed << std::setprecision(1) << mean << std::setw(17)
            << std::setprecision(3) << share << (budget == 2 ? "   (default)" : "") << "\n";
    figure("probe_budget_ms." + std::to_string(budget), mean);
    figure("probe_budget_waiting." + std::to_string(budget), share);
  }
}

}  // namespace nightcap::bench
