// The top-down map (shadow.topdown): what it costs in the street frame, what a redraw costs, and
// time against error for its resolution.
#include <iomanip>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/topdown_layout.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;

namespace nightcap::bench {

// On against off (`--set shadow.topdown.enabled=0`: the sky's diffuse light everywhere) in the
// frame frame_ms_street measures, the map's street shot walking: two renderers warmed up by frame
// 0 (which draws the map), then frames 1..repeats on each in turn; the ratio of the medians of
// the whole frame's wall clock (topdown_on_off_ratio). Then the redraw (topdown_redraw_ms): the
// reset frame's shadow.topdown_plan and shadow.topdown timed alone, at each resolution, against
// the error of the frame's lighting.lit at --hour 10 (daylight: the sky's light matters) next to
// that at 8192 texels, the RMS of the difference over the RMS of what the map changes at 8192
// (lighting.lit less that with the map off).
void bench_topdown(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## top-down sky visibility, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  street_on_off(gpu, scene, width, height, repeats, "shadow.topdown", "topdown_on_off_ratio", "topdown");

  table() << "resolution   redraw ms   lighting.lit error (share of what the map changes)\n";
  nc::Scene day = scene;
  nc::set_hour(day, 10.0);
  nc::RenderSettings still;
  still.width = width;
  still.height = height;
  still.path.motion = nc::CameraPath::Motion::still;
  still.pass_timing.reset();  // each pass timed alone on a CPU device
  const auto render = [&](const nc::RenderSettings& settings, double* redraw_ms) {
    nc::Renderer renderer(gpu, day, settings);
    const nc::RenderedFrame frame = renderer.render_frame(0, true);
    if (redraw_ms) *redraw_ms = frame_pass_ms(frame, "shadow.topdown_plan") + frame_pass_ms(frame, "shadow.topdown");
    return *frame.execution.final_version("lighting.lit")->bytes;
  };
  nc::RenderSettings without_map = still;
  without_map.params["shadow.topdown"]["enabled"] = 0.0;
  const std::vector<uint8_t> none = render(without_map, nullptr);
  const std::vector<uint32_t> resolutions = {512, 1024, 2048, 4096, 8192};
  std::vector<std::vector<uint8_t>> images;
  std::vector<double> ms(resolutions.size());
  for (size_t k = 0; k < resolutions.size(); ++k) {
    nc::RenderSettings settings = still;
    settings.params["shadow.topdown"]["resolution"] = double(resolutions[k]);
    images.push_back(render(settings, &ms[k]));
  }
  const uint64_t texels = uint64_t(width) * height;
  const double change = rgba16f_rms_difference(images.back(), none, texels);
  for (size_t k = 0; k < resolutions.size(); ++k) {
    const double error = rgba16f_rms_difference(images[k], images.back(), texels) / std::max(change, 1e-30);
    table() << std::setw(10) << resolutions[k] << std::setw(12) << std::fixed << std::setprecision(1) << ms[k]
            << std::setw(12) << std::setprecision(4) << error << (resolutions[k] == 2048 ? "   (default)" : "")
            << (k + 1 == resolutions.size() ? "   (the reference)" : "") << "\n";
    figure("topdown_redraw_ms." + std::to_string(resolutions[k]), ms[k]);
    figure("topdown_error." + std::to_string(resolutions[k]), error);
  }
  figure("topdown_redraw_ms", ms[2]);
}

}  // namespace nightcap::bench
