// The reflection probes: what they cost in the street frame, what one probe's update costs, and
// time against error for the prefilter's samples, the faces' resolution and the probes captured
// per frame.
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
// worst mip; time: the pass's GPU time. Probes captured per frame (max_updates): the street shot
// driving, a frame every second (14 m apart, so probes come in range), each frame's capture passes
// timed alone against the share of the probes in range still waiting for a capture (their
// reflections show the sky), over 12 frames after the reset.
void bench_probe_tradeoffs(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  table() << "\n## probes.convert: prefilter samples against error (synthetic capture, 64 texels a face)\n"
          << "samples at mip 1   gpu ms   worst mip RMSE\n";
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
    table() << std::setw(17) << samples << std::setw(9) << std::fixed << std::setprecision(2) << gpu_ms(run)
            << std::setw(17) << std::setprecision(4) << worst << (samples == 64 ? "   (default)" : "") << "\n";
    figure("probe_prefilter_ms." + std::to_string(samples), gpu_ms(run));
    figure("probe_prefilter_rmse." + std::to_string(samples), worst);
  }

  // Face resolution: the city block's probe captured at N texels a face against the same views
  // rendered by the frame's own passes at 256×256 (lighting.deferred and the composite, the
  // camera at the probe facing each face), box-filtered to N: relative RMSE over the six faces;
  // time: the capture's passes timed alone in its frame. The city's local lights alone, every
  // one (no sun: its shadow comes from different maps), no decals, as tests/unit/probes_capture_test.cpp.
  table() << "\n## probe face resolution against the frame's own passes at 256x256 (city block, local lights)\n"
          << "face texels   capture ms   relative RMSE\n";
  nc::Scene city = nc::build_city(1);
  std::erase_if(city.lights, [](const nc::Light& l) { return l.type == nc::LightType::directional; });
  city.decals.clear();
  std::erase_if(city.instances, [&](const nc::Instance& i) { return city.materials.at(city.material_of(i)).decal; });
  const glm::dvec3 probe = city.probes.at(0).position;
  constexpr uint32_t kReferenceSide = 256;
  std::vector<std::vector<glm::dvec3>> reference_faces;
  for (uint32_t face = 0; face < 6; ++face) {
    const glm::dvec3 centre = reference::face_point(face, 0, 0);
    const glm::dvec3 right = reference::face_point(face, 1, 0) - centre,
                     up = centre - reference::face_point(face, 0, 1);
    nc::RenderSettings settings;
    settings.width = settings.height = kReferenceSide;
    settings.lighting = nc::FrameLighting::deferred;
    settings.path.motion = nc::CameraPath::Motion::still;
    settings.params["probes"]["enabled"] = 0.0;
    nc::Camera camera;
    camera.world = glm::dmat4(glm::dvec4(-right, 0), glm::dvec4(up, 0), glm::dvec4(-centre, 0), glm::dvec4(probe, 1));
    camera.yfov = float(std::numbers::pi / 2);
    settings.camera = camera;
    nc::Renderer renderer(gpu, city, settings);
    const nc::RenderedFrame frame = renderer.render_frame(0, true);
    const VersionData& lit = *frame.execution.final_version("lighting.lit");
    std::vector<glm::dvec3> texels(kReferenceSide * kReferenceSide);
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = reference::half4_at(*lit.bytes, i * 8);
    reference_faces.push_back(std::move(texels));
  }
  for (const uint32_t side : {16u, 32u, 64u, 128u}) {
    nc::RenderSettings settings;
    settings.width = 160;
    settings.height = 90;
    settings.lighting = nc::FrameLighting::deferred;
    settings.params["probes"]["face_size"] = double(side);
    settings.params["probes.cull"]["lights"] = 256.0;
    settings.params["probes.plan"]["refresh_frames"] = 1.0;  // frame 1 captures the probe again
    nc::Renderer renderer(gpu, city, settings);
    renderer.render_frame(0, false);  // pipelines compiled outside the measurement
    const nc::RenderedFrame frame = renderer.render_frame(1, true);
    const VersionData& faces = *frame.execution.final_version("probes.faces");
    const FormatInfo f = *format_info(faces.desc.format);
    const uint32_t block = kReferenceSide / side;
    double squares = 0, signal = 0;
    for (uint32_t face = 0; face < 6; ++face)
      for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
          glm::dvec3 expected(0.0);
          // The view's pixels of cube texel x are those of column side − 1 − x (plan.cpp).
          for (uint32_t v = 0; v < block; ++v)
            for (uint32_t u = 0; u < block; ++u)
              expected += reference_faces[face][(y * block + v) * kReferenceSide + (side - 1 - x) * block + u];
          expected /= double(block * block);
          const glm::dvec3 got = reference::half4_at(
              *faces.bytes, raw_subresource_offset(f, faces.desc.extent, 0, 0, face) + (uint64_t(y) * side + x) * 8);
          squares += glm::dot(got - expected, got - expected);
          signal += glm::dot(expected, expected);
        }
    const double rmse = std::sqrt(squares / signal);
    table() << std::setw(11) << side << std::setw(13) << std::fixed << std::setprecision(1) << update_ms(frame)
            << std::setw(16) << std::setprecision(4) << rmse << (side == 64 ? "   (default)" : "") << "\n";
    figure("probe_resolution_ms." + std::to_string(side), update_ms(frame));
    figure("probe_resolution_rmse." + std::to_string(side), rmse);
  }

  table() << "\n## probes captured per frame: street shot driving, a frame a second, 12 frames after the reset\n"
          << "max_updates   capture ms/frame   probes waiting\n";
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
    table() << std::setw(11) << budget << std::setw(19) << std::fixed << std::setprecision(1) << median(ms)
            << std::setw(17) << std::setprecision(3) << share << (budget == 2 ? "   (default)" : "") << "\n";
    figure("probe_budget_ms." + std::to_string(budget), median(ms));
    figure("probe_budget_waiting." + std::to_string(budget), share);
  }
}

}  // namespace nightcap::bench
