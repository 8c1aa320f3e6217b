// The GI volume (gi.plan, gi.volume): what it costs in the street frame, and time against error
// for its spherical-harmonic order and its resolution.
#include <iomanip>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/probes/plan.h"
#include "passes/scene/time_of_day.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/gi_reference.h"

namespace nc = nightcap;

namespace nightcap::bench {
namespace {

// The irradiance error of the first `bands` bands against the exact cosine convolution over 256
// normals (gi_reference.h's sh_error()), the mean over the frame's sky (sky.cubemap's level 0
// against sky.irradiance) and its probes' captures (probes.faces' level 0 against
// probes.irradiance), each environment weighing the same.
double sh_mean_error(const nc::RenderedFrame& frame, uint32_t bands) {
  const std::vector<glm::dvec3> normals = reference::spread_normals(256);
  double sum = 0;
  int environments = 0;
  auto add = [&](const reference::CubeLevel& level, const GpuSkyIrradiance& stored) {
    std::vector<glm::dvec3> exact;
    for (const glm::dvec3& n : normals) exact.push_back(reference::diffuse_reflected(level, n));
    sum += reference::sh_error(reference::sh_coefficients(stored, bands), normals, exact).mean;
    ++environments;
  };
  const VersionData& cube = *frame.execution.final_version("sky.cubemap");
  add(reference::cube_level(*cube.bytes, cube.desc.format, cube.desc.extent.width, cube.desc.extent.mips, 0),
      host_records<GpuSkyIrradiance>(*frame.execution.final_version("sky.irradiance")->bytes).at(0));
  const nc::ProbePlan plan = nc::read_probe_plan(*frame.execution.final_version("probes.plan")->bytes);
  const VersionData& faces = *frame.execution.final_version("probes.faces");
  const auto stored = host_records<GpuSkyIrradiance>(*frame.execution.final_version("probes.irradiance")->bytes);
  for (uint32_t capture = 0; capture < plan.captured; ++capture)
    add(reference::cube_array_level(*faces.bytes, faces.desc.format, faces.desc.extent, capture, 0),
        stored.at(plan.capture_slot[capture]));
  return sum / environments;
}

}  // namespace

// On against off (`--set gi.enabled=0`: indirect diffuse from the sky's irradiance alone, as
// before the volume) in the frame frame_ms_street measures, the map's street shot walking: two
// renderers warmed up by frame 0 (which gathers the whole volume), then frames 1..repeats on
// each in turn; the ratio of the medians of the whole frame's wall clock (gi_volume_on_off_ratio).
//
// SH order: the composite's time (alone, the median of frames 1..repeats, still camera) reading
// bands 0–1 (L1: 3 texels of a cell) or 0–2 (L2: 7) against the irradiance error of those bands
// (sh_mean_error() at --hour 10). Resolution: the whole volume's gather (gi.volume on frame 0,
// alone) at 16, 32, 64 and 128 cells over the same 128 m, against lighting.lit at --hour 10 next
// to that with 128 cells: the RMS of the difference over the RMS of what the volume changes at
// 128 (lighting.lit less that with the volume off).
void bench_gi(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## GI volume, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  street_on_off(gpu, scene, width, height, repeats, "gi", "gi_volume_on_off_ratio", "gi");

  nc::Scene day = scene;
  nc::set_hour(day, 10.0);
  nc::RenderSettings still;
  still.width = width;
  still.height = height;
  still.path.motion = nc::CameraPath::Motion::still;
  still.pass_timing.reset();  // each pass timed alone on a CPU device

  table() << "SH order   composite ms   gi.volume ms (kept)   irradiance error (mean relative)\n";
  for (const uint32_t bands : {1u, 2u}) {
    nc::RenderSettings settings = still;
    settings.params["gi.plan"]["sh_order"] = double(bands);
    nc::Renderer renderer(gpu, day, settings);
    const nc::RenderedFrame first = renderer.render_frame(0, true);
    const double error = sh_mean_error(first, bands);
    std::vector<double> composite, kept;
    for (int r = 1; r <= repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
      composite.push_back(frame_pass_ms(frame, "lighting.composite"));
      kept.push_back(frame_pass_ms(frame, "gi.volume"));
    }
    const std::string key = "L" + std::to_string(bands);
    table() << std::setw(8) << key << std::setw(15) << std::setprecision(1) << median(composite) << std::setw(22)
            << median(kept) << std::setw(18) << std::setprecision(4) << error << (bands == 2 ? "   (default)" : "")
            << "\n";
    figure("gi_composite_ms." + key, median(composite));
    figure("gi_sh_error." + key, error);
    if (bands == 2) figure("gi_volume_kept_ms", median(kept));
  }

  table() << "cells   cell m   gather ms   lighting.lit error (share of what the volume changes)\n";
  const auto render = [&](const nc::RenderSettings& settings, double* gather_ms) {
    nc::Renderer renderer(gpu, day, settings);
    const nc::RenderedFrame frame = renderer.render_frame(0, true);
    if (gather_ms) *gather_ms = frame_pass_ms(frame, "gi.volume");
    return *frame.execution.final_version("lighting.lit")->bytes;
  };
  nc::RenderSettings without_volume = still;
  without_volume.params["gi"]["enabled"] = 0.0;
  const std::vector<uint8_t> none = render(without_volume, nullptr);
  const std::vector<uint32_t> resolutions = {16, 32, 64, 128};
  std::vector<std::vector<uint8_t>> images;
  std::vector<double> ms(resolutions.size());
  for (size_t k = 0; k < resolutions.size(); ++k) {
    nc::RenderSettings settings = still;
    settings.params["gi"]["cells"] = double(resolutions[k]);
    settings.params["gi.plan"]["cell_metres"] = 128.0 / resolutions[k];
    images.push_back(render(settings, &ms[k]));
  }
  const uint64_t texels = uint64_t(width) * height;
  const double change = rgba16f_rms_difference(images.back(), none, texels);
  for (size_t k = 0; k < resolutions.size(); ++k) {
    const double error = rgba16f_rms_difference(images[k], images.back(), texels) / std::max(change, 1e-30);
    table() << std::setw(5) << resolutions[k] << std::setw(9) << std::setprecision(2) << 128.0 / resolutions[k]
            << std::setw(12) << std::setprecision(1) << ms[k] << std::setw(12) << std::setprecision(4) << error
            << (resolutions[k] == 64 ? "   (default)" : "") << (k + 1 == resolutions.size() ? "   (the reference)" : "")
            << "\n";
    figure("gi_gather_ms." + std::to_string(resolutions[k]), ms[k]);
    figure("gi_resolution_error." + std::to_string(resolutions[k]), error);
  }
  figure("gi_gather_ms", ms[2]);
}

}  // namespace nightcap::bench
