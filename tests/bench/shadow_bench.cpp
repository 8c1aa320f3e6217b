// The sun's shadows (cascades and resolve, time of day, distant levels) and every shadow cache across frames.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <map>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/shadow_layout.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/shadow_reference.h"
#include "tests/unit/recorded_pass.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {

namespace {

// The shadow passes with a `cache` parameter.
constexpr const char* kShadowCaches[] = {"shadow.cull", "shadow.distant_plan", "shadow.local_plan"};

}  // namespace

// The sun's shadow: shadow.cascades and shadow.sun_resolve by timestamps on the street shot of a
// 2 km map at --size (its moon is the sun), median of --repeats frames rendered as far as
// shadow.sun; then time against error on the built-in city for the cascades' resolution and the
// resolve's filter, the error being the share of sampled pixels (every 4th of every 4th row)
// whose visibility disagrees with the CPU ray cast (tests/reference/shadow_reference.h), away
// from the ray cast's shadow edges (the unit test's measure) and everywhere.
//  - shadow_ms_street (cascades_static + cascades + resolve, frame 0), shadow_cascades_ms_street,
//  shadow_resolve_ms_street,
//    shadow_cull_ms_street (CPU), shadow_casters_street (draws over the four cascades),
//    shadow_casters_culled_street (of the casters tested, summed over the cascades)
//  - shadow.res<R>_pcf<r>.{cascades_ms, resolve_ms, disagree, disagree_everywhere}
void bench_shadows(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"shadow.sun"};
  {
    nc::Scene scene = nc::build_map({1, 2.0, nc::Shot::street});
    nc::add_default_lighting(scene);
    nc::Renderer renderer(gpu, scene, settings);
    std::vector<double> cull, cascades, resolve;
    for (int r = 0; r < repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(0, false);
      cull.push_back(frame_pass_ms(frame, "shadow.cull"));
      cascades.push_back(frame_pass_ms(frame, "shadow.cascades_static") + frame_pass_ms(frame, "shadow.cascades"));
      resolve.push_back(frame_pass_ms(frame, "shadow.sun_resolve"));
    }
    const nc::RenderedFrame captured = renderer.render_frame(0, true);
    nc::ShadowCullStats stats;
    std::memcpy(&stats, captured.execution.final_version("shadow.cull_stats")->bytes->data(), sizeof stats);
    uint32_t drawn = 0, culled = 0, tested = 0;
    for (uint32_t k = 0; k < nc::kShadowCascades; ++k) {
      drawn += stats.draws[k];
      culled += stats.casters_culled[k] + stats.casters_hidden[k];
      tested += stats.casters_tested[k];
    }
    table() << "\n## shadows: 2 km map, street shot (" << width << "x" << height << ", ms, median of " << repeats
            << ")\nshadow.cull (CPU) " << median(cull) << ", shadow.cascades_static + shadow.cascades "
            << median(cascades) << ", shadow.sun_resolve " << median(resolve) << "; casters drawn " << drawn
            << " (culled " << culled << " of " << tested << " tested, over 4 cascades)\n";
    figure("shadow_ms_street", median(cascades) + median(resolve));
    figure("shadow_cascades_ms_street", median(cascades));
    figure("shadow_resolve_ms_street", median(resolve));
    figure("shadow_cull_ms_street", median(cull));
    figure("shadow_casters_street", drawn);
    figure("shadow_casters_culled_street", culled);
  }
  nc::Scene city = nc::build_city(1);
  nc::add_default_lighting(city);
  const ref::ShadowTriangles triangles(city, glm::dvec3(nc::base_camera(city, settings).world[3]));
  table() << "\n## shadows: time against error (built-in city, " << width << "x" << height
          << "; disagreement with the CPU ray cast)\n"
          << std::left << std::setw(8) << "texels" << std::setw(8) << "filter" << std::right << std::setw(14)
          << "cascades ms" << std::setw(12) << "resolve ms" << std::setw(16) << "off edges" << std::setw(16)
          << "everywhere"
          << "\n";
  for (int resolution : {512, 1024, 2048}) {
    for (int radius : {0, 1, 2, 3}) {
      settings.params["shadow"]["resolution"] = resolution;  // shared by the cascades' passes
      settings.params["shadow.sun_resolve"]["filter_radius"] = radius;
      nc::Renderer renderer(gpu, city, settings);
      std::vector<double> cascades, resolve;
      for (int r = 0; r < repeats; ++r) {
        const nc::RenderedFrame frame = renderer.render_frame(0, false);
        cascades.push_back(frame_pass_ms(frame, "shadow.cascades_static") + frame_pass_ms(frame, "shadow.cascades"));
        resolve.push_back(frame_pass_ms(frame, "shadow.sun_resolve"));
      }
      const nc::RenderedFrame captured = renderer.render_frame(0, true);
      const auto inputs = nc::recorded_pass(captured, "shadow.sun_resolve").inputs;
      const nc::VersionData& sun = *captured.execution.final_version("shadow.sun");
      const ref::ShadowView view(inputs, {sun.desc, sun.bytes});
      const ref::ShadowAgreement a = ref::shadow_agreement(view, triangles, 4);
      const std::string row = "shadow.res" + std::to_string(resolution) + "_pcf" + std::to_string(radius);
      table() << std::left << std::setw(8) << resolution << std::setw(8) << (2 * radius + 1) << std::right << std::fixed
              << std::setprecision(1) << std::setw(14) << median(cascades) << std::setw(12) << median(resolve)
              << std::setprecision(4) << std::setw(16) << 1.0 - a.share() << std::setw(16) << 1.0 - a.share_everywhere()
              << std::defaultfloat << "\n";
      figure(row + ".cascades_ms", median(cascades));
      figure(row + ".resolve_ms", median(resolve));
      figure(row + ".disagree", 1.0 - a.share());
      figure(row + ".disagree_everywhere", 1.0 - a.share_everywhere());
    }
  }
}

// Time of day (issue 14): `bake-tod` of the 2 km map (seed 1) on this machine's cores, and on its
// street shot at 08:00, 09:00 (between baked hours) and 10:00 what the filter saves: the sun's
// triangles it drops over the four cascades against those drawn without it, shadow.cascades'
// GPU time with and without it, and the share of shadowed pixels of shadow.sun that differ.
// The shadow caches are off here: with them, every frame after the first redraws no static
// caster, so the filter would have nothing to drop and these figures would time empty layers.
//  - tod_bake_s_2km; tod_triangles_saved_ratio (street shot, 08:00)
//  - tod_triangles_saved_ratio_street_<H>h, tod_cascades_ms_street_<H>h, tod_cascades_ms_unfiltered_street_<H>h,
//    tod_disagree_street_<H>h
void bench_tod(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  const nc::Scene map = nc::build_map({1, 2.0, nc::Shot::street});
  const double start = now_ms();
  const nc::TodTable tod = nc::bake_tod(map, 1, 2.0);
  const double bake_s = (now_ms() - start) / 1000.0;
  figure("tod_bake_s_2km", bake_s);
  table() << "\n## time of day: 2 km map (seed 1), street shot (" << width << "x" << height << ")\nbake-tod: " << bake_s
          << " s on " << std::thread::hardware_concurrency() << " threads\n"
          << std::left << std::setw(8) << "hour" << std::right << std::setw(14) << "triangles" << std::setw(12)
          << "saved" << std::setw(14) << "cascades ms" << std::setw(16) << "unfiltered ms" << std::setw(12)
          << "disagree"
          << "\n";
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.path.motion = nc::CameraPath::Motion::still;
  settings.sinks = {"shadow.sun"};
  for (const char* pass : kShadowCaches) settings.params[pass]["cache"] = 0;
  for (double hour : {8.0, 9.0, 10.0}) {
    struct Run {
      double cascades_ms = 0;
      nc::ShadowCullStats stats{};
      std::vector<uint8_t> sun;
    };
    auto run = [&](bool filtered) {
      nc::Scene scene = map;
      nc::set_hour(scene, hour);
      if (filtered) {
        scene.tod_visible = tod.visible;
        scene.tod_hour = hour;
      }
      nc::Renderer renderer(gpu, scene, settings);
      renderer.render_frame(0, false);  // pipelines compiled outside the measurement
      std::vector<double> cascades;
      for (int r = 0; r < repeats; ++r) {
        const nc::RenderedFrame frame = renderer.render_frame(0, false);
        cascades.push_back(frame_pass_ms(frame, "shadow.cascades_static") + frame_pass_ms(frame, "shadow.cascades"));
      }
      const nc::RenderedFrame captured = renderer.render_frame(0, true);
      Run out;
      out.cascades_ms = median(cascades);
      std::memcpy(&out.stats, captured.execution.final_version("shadow.cull_stats")->bytes->data(), sizeof out.stats);
      out.sun = *captured.execution.final_version("shadow.sun")->bytes;
      return out;
    };
    const Run full = run(false), filtered = run(true);
    uint64_t drawn = 0, saved = 0;
    for (uint32_t k = 0; k < nc::kShadowCascades; ++k) {
      drawn += full.stats.triangles[k];
      saved += filtered.stats.tod_triangles_saved[k];
    }
    size_t shadowed = 0, differ = 0;
    for (size_t i = 0; i < full.sun.size(); i += 2) {
      if (full.sun[i] == 255 && filtered.sun[i] == 255) continue;
      ++shadowed;
      differ += full.sun[i] != filtered.sun[i];
    }
    const double ratio = drawn ? double(saved) / drawn : 0.0, disagree = shadowed ? double(differ) / shadowed : 0.0;
    const std::string suffix = "_street_" + std::to_string(int(hour)) + "h";
    table() << std::left << std::setw(8) << hour << std::right << std::setw(14) << drawn << std::setw(12) << saved
            << std::fixed << std::setprecision(2) << std::setw(14) << filtered.cascades_ms << std::setw(16)
            << full.cascades_ms << std::setprecision(5) << std::setw(12) << disagree << std::defaultfloat << "\n";
    figure("tod_triangles_saved_ratio" + suffix, ratio);
    figure("tod_cascades_ms" + suffix, filtered.cascades_ms);
    figure("tod_cascades_ms_unfiltered" + suffix, full.cascades_ms);
    figure("tod_disagree" + suffix, disagree);
    if (hour == 8.0) figure("tod_triangles_saved_ratio", ratio);
  }
}

// Every shadow across frames: frame 3 of a still camera (vehicles still move) on the street shot
// of a 2 km map at --size, rendered as far as shadow.sun and shadow.local_moments with every
// shadow cache (kShadowCaches) on and off in this process: every shadow pass's own time (CPU
// passes by their clock, GPU ones by timestamps; median of --repeats runs of frames 0 to 3), and
// the sums' ratio. The street as built (no spot light: the sun's passes), and again with 8 spot
// lights in view (add_spots_in_view), over the traffic.
//  - static_cached_vs_uncached_ratio (the sums of the shadow.* passes' times, caches on / off)
//  - shadow_cache.on_ms, shadow_cache.off_ms (those sums), shadow_cache.<pass>.{on,off}_ms
//  - shadow_cache.cascades_ratio: the same over the cascades' passes (shadow.cull,
//    shadow.cascades_static, shadow.cascades)
//  - the same with 8 spot lights: static_cached_vs_uncached_ratio_spots, shadow_cache_spots.*
//  - the same for the street driving (the cascades' static layers move and redraw the tiles they
//    uncover, the distant levels likewise): shadow_cache_drive.*, and its cascades' ratio as
//    cascades_drive_cached_vs_uncached_ratio
void bench_shadow_cache(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.path.motion = nc::CameraPath::Motion::still;
  settings.sinks = {"shadow.sun", "shadow.local_moments"};
  nc::Scene street = nc::build_map({1, 2.0, nc::Shot::street});
  nc::add_default_lighting(street);
  nc::Scene spots = street;
  add_spots_in_view(spots, width, height, 8);
  struct Case {
    const nc::Scene* scene;
    std::string suffix;
    nc::CameraPath::Motion motion;
  };
  for (const Case& c :
       {Case{&street, "", nc::CameraPath::Motion::still}, Case{&spots, "_spots", nc::CameraPath::Motion::still},
        Case{&street, "_drive", nc::CameraPath::Motion::drive}}) {
    const nc::Scene* scene = c.scene;
    const std::string& suffix = c.suffix;
    const bool still = c.motion == nc::CameraPath::Motion::still;
    settings.path.motion = c.motion;
    // Each repeat renders frames 0 to 3 with a fresh renderer (no history), the cache on and then
    // off, so that the machine's load falls on both alike.
    std::map<std::string, std::vector<double>> runs[2];
    for (int r = 0; r < repeats; ++r)
      for (int cache : {1, 0}) {
        for (const char* pass : kShadowCaches) settings.params[pass]["cache"] = cache;
        nc::Renderer renderer(gpu, *scene, settings);
        for (uint32_t i = 0; i <= 3; ++i) {
          const nc::RenderedFrame frame = renderer.render_frame(i, false);
          if (i < 3) continue;
          for (size_t p = 0; p < frame.graph.passes.size(); ++p) {
            const std::string& name = frame.graph.passes[p].decl->name;
            if (name.rfind("shadow.", 0) == 0 && frame.graph.passes[p].runs)
              runs[cache][name].push_back(frame_pass_ms(frame, name));
          }
        }
      }
    std::map<std::string, double> on, off;
    for (auto& [name, times] : runs[1]) on[name] = median(times);
    for (auto& [name, times] : runs[0]) off[name] = median(times);
    double on_sum = 0, off_sum = 0, on_cascades = 0, off_cascades = 0;
    table() << "\n## shadows across frames: 2 km map, street shot" << (suffix == "_spots" ? ", 8 spot lights" : "")
            << (still ? ", still camera (" : ", driving (") << width << "x" << height << "), frame 3, ms, median of "
            << repeats << "\n"
            << std::left << std::setw(26) << "pass" << std::right << std::setw(12) << "cache on" << std::setw(12)
            << "cache off\n";
    const std::string prefix = "shadow_cache" + suffix;
    for (const auto& [name, off_ms] : off) {
      const double on_ms = on.count(name) ? on.at(name) : 0.0;
      on_sum += on_ms;
      off_sum += off_ms;
      if (name == "shadow.cull" || name == "shadow.cascades_static" || name == "shadow.cascades") {
        on_cascades += on_ms;
        off_cascades += off_ms;
      }
      table() << std::left << std::setw(26) << name << std::right << std::fixed << std::setprecision(3) << std::setw(12)
              << on_ms << std::setw(12) << off_ms << std::defaultfloat << "\n";
      figure(prefix + "." + name + ".on_ms", on_ms);
      figure(prefix + "." + name + ".off_ms", off_ms);
    }
    const double ratio = off_sum > 0 ? on_sum / off_sum : 0.0;
    const double cascades_ratio = off_cascades > 0 ? on_cascades / off_cascades : 0.0;
    table() << "every shadow pass: " << on_sum << " against " << off_sum << " ms, ratio " << ratio
            << " (target <= 0.6); the cascades' passes (shadow.cull, shadow.cascades_static, shadow.cascades): "
            << on_cascades << " against " << off_cascades << " ms, ratio " << cascades_ratio << "\n";
    figure(prefix + ".cascades_ratio", cascades_ratio);
    figure(prefix + ".on_ms", on_sum);
    figure(prefix + ".off_ms", off_sum);
    if (still)
      figure("static_cached_vs_uncached_ratio" + suffix, ratio);
    else
      figure("cascades_drive_cached_vs_uncached_ratio", cascades_ratio);
  }
}

// The cascades' static refresh while driving, time against error over shadow.cull's budget: the
// 2 km map's street shot at --size, 24 frames with a fresh renderer per budget. Per budget: the
// median over frames 1–23 of shadow.cull + shadow.cascades_static (ms) and of the static
// triangles drawn, the most tiles pending after a frame, and the error: the share of shadow.sun's
// pixels at frame 23 that differ from a render with the cache off (pending tiles make pixels fall
// back to coarser maps).
//  - shadow.cascades_budget<B>.{ms, triangles, pending_max, sun_differs}
void bench_cascade_budget(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.path.motion = nc::CameraPath::Motion::drive;
  settings.sinks = {"shadow.sun"};
  nc::Scene street = nc::build_map({1, 2.0, nc::Shot::street});
  nc::add_default_lighting(street);
  constexpr uint32_t kFrames = 24;
  auto sun_of = [](const nc::RenderedFrame& frame) {
    for (const nc::VersionData& v : frame.execution.versions)
      if (v.resource == "shadow.sun" && v.bytes) return *v.bytes;
    return std::vector<uint8_t>();
  };
  std::vector<uint8_t> reference;
  {
    settings.params["shadow.cull"]["cache"] = 0;
    nc::Renderer renderer(gpu, street, settings);
    for (uint32_t i = 0; i < kFrames; ++i) {
      const nc::RenderedFrame frame = renderer.render_frame(i, i + 1 == kFrames);
      if (i + 1 == kFrames) reference = sun_of(frame);
    }
    settings.params["shadow.cull"]["cache"] = 1;
  }
  table() << "\n## cascades' static refresh while driving: 2 km map, street shot (" << width << "x" << height
          << "), frames 1-" << kFrames - 1 << "\n"
          << std::left << std::setw(12) << "budget" << std::right << std::setw(12) << "ms" << std::setw(12)
          << "triangles" << std::setw(14) << "pending max" << std::setw(22) << "shadow.sun differs\n";
  for (const uint32_t budget : {10000u, 30000u, 100000u, 500000u}) {
    settings.params["shadow.cull"]["budget_triangles"] = budget;
    nc::Renderer renderer(gpu, street, settings);
    std::vector<double> ms, triangles;
    uint32_t pending_max = 0;
    double differs = 0.0;
    for (uint32_t i = 0; i < kFrames; ++i) {
      const bool last = i + 1 == kFrames;
      const nc::RenderedFrame frame = renderer.render_frame(i, true);
      if (i == 0) continue;
      ms.push_back(frame_pass_ms(frame, "shadow.cull") + frame_pass_ms(frame, "shadow.cascades_static"));
      for (const nc::VersionData& v : frame.execution.versions)
        if (v.resource == "shadow.cull_stats" && v.bytes && v.bytes->size() == sizeof(nc::ShadowCullStats)) {
          nc::ShadowCullStats stats;
          std::memcpy(&stats, v.bytes->data(), sizeof stats);
          triangles.push_back(stats.static_triangles);
          pending_max = std::max(pending_max, stats.pending);
        }
      if (!last) continue;
      const std::vector<uint8_t> sun = sun_of(frame);
      size_t count = 0;
      for (size_t p = 0; p < sun.size() && sun.size() == reference.size(); p += 2) count += sun[p] != reference[p];
      differs = sun.empty() ? 0.0 : double(count) / double(sun.size() / 2);
    }
    const std::string name = "shadow.cascades_budget" + std::to_string(budget);
    table() << std::left << std::setw(12) << budget << std::right << std::fixed << std::setprecision(3) << std::setw(12)
            << median(ms) << std::setw(12) << std::setprecision(0) << median(triangles) << std::setw(14) << pending_max
            << std::setw(21) << std::setprecision(5) << differs << std::defaultfloat << "\n";
    figure(name + ".ms", median(ms));
    figure(name + ".triangles", median(triangles));
    figure(name + ".pending_max", pending_max);
    figure(name + ".sun_differs", differs);
  }
}

// The sun's distant shadow (shadow.distant_plan on the CPU, shadow.distant by timestamps) at
// --size. A still camera on the 16 km map's street shot (the default render's): frame 0 draws
// every level, later frames only carry the levels over. Then time against error over the
// per-frame budget on the 2 km map's street shot, driving, with 32 m finest levels cut into 4×4
// tiles (a level-0 move every 17 frames or so): the levels' stale texels after 60 frames, against
// a render of that frame with no history (every level drawn).
//  - shadow_distant_ms (still, frames 1–3, median), shadow_distant_full_ms (frame 0),
//    shadow_distant_plan_ms (CPU, frames 1–3)
//  - shadow.distant_budget<B>.{ms, triangles, pending_max, stale}: per frame median ms and
//    triangles while driving, the most units waiting after a frame, and the share of texels more
//    than a quarter texel of depth from the full render after frame 59
void bench_distant(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"shadow.sun"};
  auto plan_of = [](const nc::RenderedFrame& frame) {
    return nc::host_records<nc::DistantPlan>(
               std::span<const uint8_t>(*frame.execution.final_version("shadow.distant_plan")->bytes))
        .at(0);
  };
  {
    settings.path.motion = nc::CameraPath::Motion::still;
    nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
    nc::add_default_lighting(scene);
    nc::Renderer renderer(gpu, scene, settings);
    double full_ms = 0;
    std::vector<double> ms, plan_ms;
    for (uint32_t i = 0; i < 4; ++i) {
      const nc::RenderedFrame frame = renderer.render_frame(i, false);
      if (i == 0) {
        full_ms = frame_pass_ms(frame, "shadow.distant");
        continue;
      }
      ms.push_back(frame_pass_ms(frame, "shadow.distant"));
      plan_ms.push_back(frame_pass_ms(frame, "shadow.distant_plan"));
    }
    table() << "\n## distant shadows: 16 km map, street shot (" << width << "x" << height << ", still camera)\n"
            << "frame 0 (every level drawn) shadow.distant " << full_ms << " ms; frames 1-3 (carried over, median) "
            << median(ms) << " ms, shadow.distant_plan (CPU) " << median(plan_ms) << " ms\n";
    figure("shadow_distant_ms", median(ms));
    figure("shadow_distant_full_ms", full_ms);
    figure("shadow_distant_plan_ms", median(plan_ms));
  }
  settings.path.motion = nc::CameraPath::Motion::drive;
  nc::Scene scene = nc::build_map({1, 2.0, nc::Shot::street});
  nc::add_default_lighting(scene);
  settings.params["shadow.distant_plan"]["level0_metres"] = 32;
  settings.params["shadow.distant_plan"]["tiles"] = 4;
  constexpr uint32_t kFrames = 60;
  std::vector<uint8_t> full;
  {
    nc::Renderer renderer(gpu, scene, settings);
    full = *renderer.render_frame(kFrames - 1, true).execution.final_version("shadow.distant")->bytes;
  }
  table() << "\n## distant shadows: time against error over the per-frame budget (2 km map, driving, " << kFrames
          << " frames, 4x4 tiles; stale: texels a quarter texel of depth or more from a full render)\n"
          << std::left << std::setw(12) << "budget" << std::right << std::setw(12) << "ms/frame" << std::setw(12)
          << "triangles" << std::setw(14) << "pending max" << std::setw(12) << "stale\n";
  for (double budget : {20.0, 100.0, 500.0, 1e9}) {
    settings.params["shadow.distant_plan"]["budget_triangles"] = budget;
    nc::Renderer renderer(gpu, scene, settings);
    std::vector<double> ms, triangles;
    uint32_t pending_max = 0;
    std::vector<uint8_t> levels;
    nc::GpuDistantLevels data{};
    for (uint32_t i = 0; i < kFrames; ++i) {
      const bool last = i + 1 == kFrames;
      const nc::RenderedFrame frame = renderer.render_frame(i, last);
      const nc::DistantPlan plan = plan_of(frame);
      if (i > 0) {
        ms.push_back(frame_pass_ms(frame, "shadow.distant"));
        triangles.push_back(plan.triangles);
        pending_max = std::max(pending_max, plan.pending);
      }
      if (last) {
        levels = *frame.execution.final_version("shadow.distant")->bytes;
        data = nc::host_records<nc::GpuDistantLevels>(
                   std::span<const uint8_t>(*frame.execution.final_version("shadow.distant_data")->bytes))
                   .at(0);
      }
    }
    const size_t texels = std::min(levels.size(), full.size()) / 4, per_level = texels / nc::kDistantLevels;
    size_t stale = 0;
    for (size_t t = 0; t < texels; ++t) {
      float a, b;
      std::memcpy(&a, &levels[4 * t], 4);
      std::memcpy(&b, &full[4 * t], 4);
      const size_t k = t / std::max<size_t>(per_level, 1);
      stale += std::abs(double(a) - double(b)) * data.depth_metres[int(k)] / data.texel_metres[int(k)] >= 0.25;
    }
    const double share = texels ? double(stale) / double(texels) : 0.0;
    const std::string row = "shadow.distant_budget" + std::to_string(int64_t(budget));
    table() << std::left << std::setw(12) << int64_t(budget) << std::right << std::fixed << std::setprecision(2)
            << std::setw(12) << median(ms) << std::setprecision(0) << std::setw(12) << median(triangles)
            << std::setw(14) << pending_max << std::setprecision(5) << std::setw(12) << share << std::defaultfloat
            << "\n";
    figure(row + ".ms", median(ms));
    figure(row + ".triangles", median(triangles));
    figure(row + ".pending_max", pending_max);
    figure(row + ".stale", share);
  }
}

}  // namespace nightcap::bench
