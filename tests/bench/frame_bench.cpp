// Whole frames, pass by pass: the built-in city, the glTF models, the 16 km map's shots, an empty scene.
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <map>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/core/isolated.h"
#include "passes/cull/cull_stats.h"
#include "passes/cull/stage.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "passes/scene/time_of_day.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;

namespace nightcap::bench {

namespace {

// Frames measured two ways, alternating so that both see the same machine: the frame's wall
// clock from a renderer that runs the frame as a whole (PassTiming::overlapped, as a frame
// runs when its passes are not being timed), and each pass's time from one that times its
// passes alone (the renderer's default on a CPU device; overlapped too on a GPU).
struct FrameMeasures {
  std::vector<double> frame_ms;
  std::map<std::string, std::vector<double>> pass_ms;  // passes that ran
  std::vector<std::string> order;                      // every pass, in frame order
  std::map<std::string, std::string> skipped;          // pass -> why, in the first measured frame
  uint64_t memory = 0, memory_without_aliasing = 0;
};

// Renders frame 0 on both renderers first (pipelines compiled outside the measurement), then
// each of `frames` on one, then on the other.
FrameMeasures measure_frames(nc::Renderer& whole, nc::Renderer& timed, const std::vector<uint32_t>& frames) {
  whole.render_frame(0, false);
  timed.render_frame(0, false);
  FrameMeasures m;
  for (size_t r = 0; r < frames.size(); ++r) {
    const double start = now_ms();
    const nc::RenderedFrame frame = whole.render_frame(frames[r], false);
    m.frame_ms.push_back(now_ms() - start);
    m.memory = frame.execution.memory_bytes;
    m.memory_without_aliasing = frame.execution.memory_bytes_without_aliasing;
    const nc::RenderedFrame passes = timed.render_frame(frames[r], false);
    for (size_t i = 0; i < passes.graph.passes.size(); ++i) {
      const nc::CompiledPass& pass = passes.graph.passes[i];
      if (r == 0) {
        m.order.push_back(pass.decl->name);
        if (!pass.runs) m.skipped[pass.decl->name] = pass.reason;
      }
      if (pass.runs) m.pass_ms[pass.decl->name].push_back(passes.execution.passes[i].time_ms);
    }
  }
  return m;
}

// One row per pass (its median, or why it was skipped), each recorded as `prefix`.PASS.
void pass_table(const FrameMeasures& m, const std::string& prefix) {
  for (const std::string& name : m.order) {
    table() << std::left << std::setw(22) << name << std::right << std::setw(12);
    const auto times = m.pass_ms.find(name);
    if (times == m.pass_ms.end()) {
      const auto reason = m.skipped.find(name);
      table() << "skipped" << (reason == m.skipped.end() ? "" : " (" + reason->second + ")") << "\n";
      continue;
    }
    table() << std::fixed << std::setprecision(3) << median(times->second) << "\n";
    figure(prefix + "." + name, median(times->second));
  }
}

nc::RenderSettings overlapped(nc::RenderSettings settings) {
  settings.pass_timing = nc::PassTiming::overlapped;
  return settings;
}

}  // namespace

// Per-pass medians over `repeats` frames, capture off, and the frame's GPU memory; with
// `capture_figures`, frame time off/on and capture size too, and the unsuffixed figures.
void bench_scene(nc::GpuDevice& gpu, const std::string& key, const std::string& label, nc::Scene scene, uint32_t width,
                 uint32_t height, int repeats, bool capture_figures) {
  nc::add_default_lighting(scene);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  nc::Renderer whole(gpu, scene, overlapped(settings)), timed(gpu, scene, settings);
  const FrameMeasures m = measure_frames(whole, timed, std::vector<uint32_t>(size_t(repeats), 0));
  table() << "\n## " << label << " (" << width << "x" << height << ", " << scene.indices.size() / 3 << " triangles, "
          << scene.lights.size() << " lights; median of " << repeats << "; passes timed "
          << nc::pass_timing_name(timed.pass_timing()) << ")\n";
  table() << std::left << std::setw(22) << "pass" << std::right << std::setw(12) << "ms"
          << "\n";
  pass_table(m, "pass_ms." + key);
  figure("frame_ms." + key, median(m.frame_ms));
  table() << std::left << std::setw(22) << "frame (capture off)" << std::right << std::setw(12) << median(m.frame_ms)
          << "\n";
  // Device memory of the frame's resources: transients sharing memory where their lifetimes
  // allow, and each in its own.
  const double mib = m.memory / 1048576.0, mib_apart = m.memory_without_aliasing / 1048576.0;
  table() << std::left << std::setw(22) << "GPU memory (MiB)" << std::right << std::setw(12) << std::setprecision(1)
          << mib << "  (" << mib_apart << " without aliasing)\n";
  figure("peak_gpu_mib." + key, mib);
  figure("peak_gpu_mib_no_aliasing." + key, mib_apart);
  if (!capture_figures) return;
  figure("peak_gpu_mib", mib);
  figure("peak_gpu_mib_no_aliasing", mib_apart);
  bench_capture_cost(whole, overlapped(settings), repeats);
}

// The built-in 16 km map, one shot at a time: cull.main alone (median of 5 runs on this
// thread, so one core: hierarchy walk, occlusion raster, tests and sort), then frames of the
// shot at the output size (the first one warms the pipelines; the camera walks), per pass.
void bench_map(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height, int repeats,
               bool frames) {
  for (nc::Shot shot : {nc::Shot::street, nc::Shot::rooftop, nc::Shot::aerial}) {
    const std::string name = nc::shot_name(shot);
    const nc::Scene scene = nc::build_map({1, 16.0, shot});
    const nc::Imports imports = nc::scene_imports(scene);
    std::map<std::string, nc::IsolatedInput> inputs;
    for (const char* resource :
         {"scene.instances", "scene.meshes", "scene.hierarchy", "scene.materials", "scene.geometry", "scene.decals"})
      inputs[resource] = {imports.at(resource).desc, imports.at(resource).bytes};
    const nc::ImportedData camera =
        nc::camera_import(*scene.camera, *scene.camera, width, height, 0, false).at("frame.camera");
    inputs["frame.camera"] = {camera.desc, camera.bytes};
    const nc::PassDecl cull = nc::cull_main_pass();
    std::vector<double> cull_ms;
    nc::CullStats stats{};
    for (int r = 0; r < 5; ++r) {
      nc::IsolatedRun run =
          nc::run_isolated(gpu, cache, cull, inputs, cull.default_params(), width, height, nc::builtin_shaders());
      cull_ms.push_back(run.execution.passes.at(0).cpu_ms);
      std::memcpy(&stats, run.outputs.at("cull.stats")->data(), sizeof(stats));
    }
    table() << "\n## map " << name << " shot (16 km, " << scene.instances.size() << " instances)\n"
            << "cull.main " << std::fixed << std::setprecision(3) << median(cull_ms)
            << " ms (median of 5): " << stats.visible << " visible, " << stats.culled_frustum << " culled by frustum, "
            << stats.culled_occlusion << " by occlusion, " << stats.culled_distance << " by distance; "
            << stats.occluders << " occluders (" << stats.occluder_triangles << " triangles); "
            << stats.draws_gbuffer + stats.draws_dynamic << " draws, "
            << stats.triangles_gbuffer + stats.triangles_dynamic << " triangles; levels of detail "
            << stats.lod_histogram[0] << "/" << stats.lod_histogram[1] << "/" << stats.lod_histogram[2] << "\n";
    figure("cull_ms_" + name, median(cull_ms));
    figure("instances_visible_" + name, stats.visible);
    figure("triangles_" + name, stats.triangles_gbuffer + stats.triangles_dynamic);
    figure("draws_" + name, stats.draws_gbuffer + stats.draws_dynamic);
    if (!frames) continue;
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.frames = uint32_t(repeats) + 1;
    nc::Renderer whole(gpu, scene, overlapped(settings)), timed(gpu, scene, settings);
    std::vector<uint32_t> walk;
    for (int r = 1; r <= repeats; ++r) walk.push_back(uint32_t(r));
    const FrameMeasures m = measure_frames(whole, timed, walk);
    table() << "frames at " << width << "x" << height << " (" << scene.lights.size() << " lights; median of " << repeats
            << ")\n";
    pass_table(m, "pass_ms.map_" + name);
    table() << std::left << std::setw(22) << "frame" << std::right << std::setw(12) << median(m.frame_ms) << "\n";
    figure("frame_ms_" + name, median(m.frame_ms));
  }
}

// An empty scene (no mesh, no light): what a frame costs when there is nothing to draw. The
// second frame is measured (frame 0 compiles the pipelines); each repeat renders the next frame,
// the camera walking, with the history of the one before.
void bench_empty(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  const nc::Scene scene;
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  nc::Renderer whole(gpu, scene, overlapped(settings)), timed(gpu, scene, settings);
  std::vector<uint32_t> walk;
  for (int r = 1; r <= repeats; ++r) walk.push_back(uint32_t(r));
  const FrameMeasures m = measure_frames(whole, timed, walk);
  table() << "\n## empty scene at " << width << "x" << height << " (frames 1.." << repeats << ", median)\n";
  pass_table(m, "pass_ms.empty");
  table() << std::left << std::setw(22) << "frame" << std::right << std::setw(12) << median(m.frame_ms) << "\n";
  figure("frame_ms_empty", median(m.frame_ms));
}

// The sky and its image-based light on against off (`--set sky.enabled=0`: the composite's constant
// sky and ambient alone) in the frame frame_ms_street measures, the map's street shot walking, at
// the default night and at --hour 17: two renderers warmed up by frame 0, then frames 1..repeats
// on each in turn, so that both see the same machine. The ratio of the medians of the whole
// frame's wall clock, per hour, and the larger as sky_ibl_on_off_ratio.
void bench_sky_ibl_cost(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## sky and image-based light on/off, map street shot at " << width << "x" << height << " (median of "
          << repeats << " alternating frames)\n";
  double largest = 0;
  for (const auto& [key, hour] : std::vector<std::pair<std::string, double>>{{"night", -1.0}, {"hour17", 17.0}}) {
    nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
    if (hour >= 0) nc::set_hour(scene, hour);
    nc::RenderSettings on;
    on.width = width;
    on.height = height;
    on.frames = uint32_t(repeats) + 1;
    on = overlapped(on);
    nc::RenderSettings off = on;
    off.params["sky"]["enabled"] = 0.0;
    const OnOffMedians cost = alternate_frames(gpu, scene, on, off, repeats);
    const double ratio = cost.ratio();
    largest = std::max(largest, ratio);
    table() << std::left << std::setw(10) << key << std::right << std::fixed << std::setprecision(1) << "on "
            << cost.on_ms << " ms, off " << cost.off_ms << " ms, ratio " << std::setprecision(3) << ratio << "\n";
    figure("sky_ibl_on_off_ratio." + key, ratio);
    figure("frame_ms_street_sky_on." + key, cost.on_ms);
    figure("frame_ms_street_sky_off." + key, cost.off_ms);
  }
  figure("sky_ibl_on_off_ratio", largest);
}

}  // namespace nightcap::bench
