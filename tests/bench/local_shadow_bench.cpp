// Spot light shadows: their passes' time, the umbra leak, resolution and blur against error, the cache across frames.
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/scene/scene.h"
#include "passes/shadow/local_layout.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/local_shadow_reference.h"
#include "tests/unit/recorded_pass.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {

namespace {

// Frame 3 of a still camera over `scene`, shadow.local_plan.cache on and off, in this process:
// the four local shadow passes' own times (median of `repeats` runs of frames 0 to 3), figures
// under `prefix`.
void bench_local_cache(nc::GpuDevice& gpu, const nc::Scene& scene, nc::RenderSettings settings, int repeats,
                       const std::string& prefix, const std::string& title) {
  settings.path.motion = nc::CameraPath::Motion::still;
  settings.sinks = {"shadow.local_moments"};
  settings.params.clear();
  const std::vector<std::string> passes{"shadow.local_plan", "shadow.local_static", "shadow.local",
                                        "shadow.local_moments"};
  nc::LocalShadowPlan plan{};
  auto frame3 = [&](double cache) {
    settings.params["shadow.local_plan"]["cache"] = cache;
    nc::Renderer renderer(gpu, scene, settings);
    std::map<std::string, std::vector<double>> runs;
    for (int r = 0; r < repeats; ++r)
      for (uint32_t i = 0; i <= 3; ++i) {
        const nc::RenderedFrame frame = renderer.render_frame(i, i == 3 && r == 0);
        if (i < 3) continue;
        for (const std::string& name : passes) runs[name].push_back(frame_pass_ms(frame, name));
        if (r == 0 && cache != 0)
          std::memcpy(&plan, frame.execution.final_version("shadow.local_plan")->bytes->data(), sizeof plan);
      }
    std::map<std::string, double> result;
    for (auto& [name, times] : runs) result[name] = median(times);
    return result;
  };
  const std::map<std::string, double> on = frame3(1), off = frame3(0);
  double on_sum = 0, off_sum = 0;
  table() << "\n## local shadows across frames: " << title << ", still camera (" << settings.width << "x"
          << settings.height << "), frame 3, ms, median of " << repeats << "\n";
  for (const std::string& name : passes) {
    on_sum += on.at(name);
    off_sum += off.at(name);
    table() << name << ": " << on.at(name) << " cache on, " << off.at(name) << " off\n";
    figure(prefix + "." + name + ".on_ms", on.at(name));
    figure(prefix + "." + name + ".off_ms", off.at(name));
  }
  const double ratio = off_sum > 0 ? on_sum / off_sum : 0.0;
  table() << "the four: " << on_sum << " against " << off_sum << " ms, ratio " << ratio << "; cache on: " << plan.maps
          << " maps, " << plan.reused << " reused, " << plan.draws << " draws (moving casters)\n";
  figure(prefix + ".on_ms", on_sum);
  figure(prefix + ".off_ms", off_sum);
  figure(prefix + ".ratio", ratio);
  figure(prefix + ".reused_maps", plan.reused);
  if (prefix == "local_cache") figure("local_cached_vs_uncached_ratio", ratio);
}

}  // namespace

// Spot light shadows (shadow.local_plan, shadow.local, shadow.local_moments; issue 14 item 4):
// their time on the built-in city's street (its spot lights) and lighting.tiled's with and
// without them, with the default settings (4 moments) and for each of shadow.local_plan's
// `moments` (4: moment shadow maps, msm4; 2: VSM); the umbra leak of both under two stacked
// occluders, plain (local_bleeding 0, accuracy.md's baseline for VSM) and with the default
// light-bleeding reduction; resolution × blur radius (default settings) against the
// disagreement with the ray cast (tests/reference/local_shadow_reference.h); the cache: frame 3
// of a still camera with shadow.local_plan.cache on and off, in this process (CPU passes by
// their clock, GPU ones by timestamps; median of --repeats runs of frames 0 to 3).
//  - local_plan_ms_city, local_ms_city, local_moments_ms_city, local_maps_city,
//    local_tiled_ms_city, local_tiled_ms_city_unshadowed (frame 0, the cache off: every map drawn)
//  - local_moments_ms_city_{msm4,vsm}, local_tiled_ms_city_{msm4,vsm}
//  - local_cache.on_ms, local_cache.off_ms: shadow.local_plan + shadow.local_static + shadow.local +
//    shadow.local_moments, frame 3; local_cached_vs_uncached_ratio (on / off);
//    local_cache.<pass>.{on,off}_ms; local_cache.reused_maps (frame 3, cache on)
//  - local_cache_map.*: the same on the 2 km map's street shot with 8 spot lights over its first
//    60 m (add_spots_in_view); local_cache_boxes.*: 1 600 small boxes under 4 spot lights, maps
//    with many static casters
//  - local_leak_{max,mean}_{vsm,msm4}[_low][_bleed0.2]: the lower occluder 2 m up (_low: 0.5 m),
//    plain or with local_bleeding 0.2
//  - local.res<R>_blur<B>.{map_ms,moments_ms,disagree,mean_error}, and local.res512_blur1_vsm.*
void bench_local(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"lighting.diffuse"};
  {
    nc::Scene city = nc::build_city(1);
    nc::add_default_lighting(city);
    std::map<std::string, std::vector<double>> ms;
    uint32_t maps = 0;
    for (int shadowed = 1; shadowed >= 0; --shadowed) {
      settings.params["shadow.local_plan"]["max_maps"] = shadowed ? 8 : 0;
      settings.params["shadow.local_plan"]["cache"] = 0;  // repeated frames would reuse the maps
      nc::Renderer renderer(gpu, city, settings);
      for (int r = 0; r < repeats; ++r) {
        const nc::RenderedFrame frame = renderer.render_frame(0, false);
        const std::string suffix = shadowed ? "" : "_unshadowed";
        ms["tiled" + suffix].push_back(frame_pass_ms(frame, "lighting.tiled"));
        if (!shadowed) continue;
        ms["plan"].push_back(frame_pass_ms(frame, "shadow.local_plan"));
        ms["map"].push_back(frame_pass_ms(frame, "shadow.local"));
        ms["moments"].push_back(frame_pass_ms(frame, "shadow.local_moments"));
      }
      if (shadowed) {
        const nc::RenderedFrame captured = renderer.render_frame(0, true);
        nc::LocalShadowPlan plan;
        std::memcpy(&plan, captured.execution.final_version("shadow.local_plan")->bytes->data(), sizeof plan);
        maps = plan.maps;
      }
    }
    // Each variant of the moments: shadow.local_moments and lighting.tiled, their frames
    // alternating so that the machine's load drifts over both alike.
    {
      std::map<std::string, std::unique_ptr<nc::Renderer>> variants;
      settings.params["shadow.local_plan"]["max_maps"] = 8;
      for (int moments : {4, 2}) {
        settings.params["shadow.local_plan"]["moments"] = moments;
        auto& renderer = variants[moments == 4 ? "msm4" : "vsm"];
        renderer = std::make_unique<nc::Renderer>(gpu, city, settings);
        renderer->render_frame(0, false);  // pipelines compiled outside the measurement
      }
      for (int r = 0; r < repeats; ++r)
        for (auto& [variant, renderer] : variants) {
          const nc::RenderedFrame frame = renderer->render_frame(0, false);
          ms["moments_" + variant].push_back(frame_pass_ms(frame, "shadow.local_moments"));
          ms["tiled_" + variant].push_back(frame_pass_ms(frame, "lighting.tiled"));
        }
    }
    settings.params.clear();
    table() << "\n## local shadows: built-in city (" << width << "x" << height << ", ms, median of " << repeats
            << ")\nshadow.local_plan (CPU) " << median(ms["plan"]) << ", shadow.local " << median(ms["map"])
            << ", shadow.local_moments " << median(ms["moments"]) << " (" << maps << " maps); lighting.tiled "
            << median(ms["tiled"]) << " with them, " << median(ms["tiled_unshadowed"]) << " without\n"
            << "4 moments: shadow.local_moments " << median(ms["moments_msm4"]) << ", lighting.tiled "
            << median(ms["tiled_msm4"]) << "; 2 moments (VSM): " << median(ms["moments_vsm"]) << ", "
            << median(ms["tiled_vsm"]) << "\n";
    figure("local_plan_ms_city", median(ms["plan"]));
    figure("local_ms_city", median(ms["map"]));
    figure("local_moments_ms_city", median(ms["moments"]));
    figure("local_maps_city", maps);
    figure("local_tiled_ms_city", median(ms["tiled"]));
    figure("local_tiled_ms_city_unshadowed", median(ms["tiled_unshadowed"]));
    for (const char* variant : {"msm4", "vsm"}) {
      figure(std::string("local_moments_ms_city_") + variant, median(ms[std::string("moments_") + variant]));
      figure(std::string("local_tiled_ms_city_") + variant, median(ms[std::string("tiled_") + variant]));
    }

    bench_local_cache(gpu, city, settings, repeats, "local_cache", "built-in city");
    nc::Scene street = nc::build_map({1, 2.0, nc::Shot::street});
    nc::add_default_lighting(street);
    add_spots_in_view(street, width, height, 8);
    bench_local_cache(gpu, street, settings, repeats, "local_cache_map", "2 km map, street shot, 8 spot lights");
    // Many static casters per map: 1 600 small boxes (19 200 triangles) under 4 spot lights.
    std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes;
    for (int k = 0; k < 1600; ++k)
      boxes.push_back({{-10.0 + 0.5 * (k % 40), 0.15 + 0.1 * (k % 3), -10.0 + 0.5 * (k / 40)}, {0.12, 0.15, 0.12}});
    std::vector<nc::Light> spots;
    for (int k = 0; k < 4; ++k)
      spots.push_back(ref::spot_light({-5.0 + 10.0 * (k % 2), 6.0, -5.0 + 10.0 * (k / 2)}, {0.0f, -1.0f, 0.0f}, 15.0f));
    bench_local_cache(gpu, ref::boxes_scene(boxes, spots, {0.0, 14.0, 16.0}, {0.0, 0.0, 0.0}), settings, repeats,
                      "local_cache_boxes", "1 600 boxes under 4 spot lights");
  }
  // Lighting with and without the maps at 480×270 (the unit test's size), and the comparison.
  auto compare = [&](const nc::Scene& scene, const glm::dvec3& eye, std::map<std::string, nc::ParamValues> params,
                     std::map<std::string, double>* pass_ms) {
    nc::RenderSettings s;
    s.width = 480;
    s.height = 270;
    s.sinks = {"lighting.diffuse"};
    s.params = params;
    nc::Renderer shadowed(gpu, scene, s);
    if (pass_ms) {
      std::vector<double> map, moments;
      for (int r = 0; r < repeats; ++r) {
        const nc::RenderedFrame frame = shadowed.render_frame(0, false);
        map.push_back(frame_pass_ms(frame, "shadow.local_static") + frame_pass_ms(frame, "shadow.local"));
        moments.push_back(frame_pass_ms(frame, "shadow.local_moments"));
      }
      (*pass_ms)["map"] = median(map);
      (*pass_ms)["moments"] = median(moments);
    }
    const nc::RenderedFrame with = shadowed.render_frame(0, true);
    s.params["shadow.local_plan"]["max_maps"] = 0;
    nc::Renderer open(gpu, scene, s);
    const nc::RenderedFrame without = open.render_frame(0, true);
    const nc::RecordedPass lit = nc::recorded_pass(with, "lighting.tiled");
    const nc::RecordedPass unlit = nc::recorded_pass(without, "lighting.tiled");
    const double resolution =
        params["shadow.local_static"].count("resolution") ? params["shadow.local_static"]["resolution"] : 512;
    const double blur =
        params["shadow.local_moments"].count("blur_radius") ? params["shadow.local_moments"]["blur_radius"] : 1;
    return ref::compare_local_shadow(scene, eye, lit.inputs, lit.outputs.at("lighting.diffuse"),
                                     unlit.outputs.at("lighting.diffuse"), resolution, blur, 2);
  };
  table() << "\n## local shadows: umbra leak under two stacked occluders (2-moment VSM, 4-moment MSM)\n";
  for (int moments : {2, 4})
    for (double lower : {2.0, 0.5})
      for (double bleeding : {0.0, 0.2}) {
        const ref::LocalComparison c =
            compare(ref::stacked_occluders_scene(lower), ref::kStackedEye,
                    {{"shadow.local_plan", {{"moments", moments}}}, {"lighting.tiled", {{"local_bleeding", bleeding}}}},
                    nullptr);
        const std::string suffix = std::string(moments == 4 ? "_msm4" : "_vsm") + (lower < 1.0 ? "_low" : "") +
                                   (bleeding > 0 ? "_bleed0.2" : "");
        table() << moments << " moments, lower occluder " << lower << " m up, local_bleeding " << bleeding << ": max "
                << c.umbra_max << ", mean " << c.umbra_mean() << " over " << c.ray_shadowed << " umbra pixels\n";
        figure("local_leak_max" + suffix, c.umbra_max);
        figure("local_leak_mean" + suffix, c.umbra_mean());
      }
  table() << "\n## local shadows: time against error (one spot over two boxes, 480x270; disagreement with the "
             "CPU ray cast off edges)\n"
          << std::left << std::setw(8) << "texels" << std::setw(8) << "blur" << std::right << std::setw(10) << "map ms"
          << std::setw(12) << "moments ms" << std::setw(12) << "disagree" << std::setw(12) << "mean |err|"
          << "\n";
  // The default settings (4 moments), then VSM at the default resolution and blur.
  struct Row {
    int resolution, blur;
    bool vsm;
  };
  std::vector<Row> rows;
  for (int resolution : {256, 512, 1024})
    for (int blur : {0, 1, 2}) rows.push_back({resolution, blur, false});
  rows.push_back({512, 1, true});
  for (const auto& [resolution, blur, vsm] : rows) {
    std::map<std::string, double> pass_ms;
    std::map<std::string, nc::ParamValues> params{{"shadow.local_static", {{"resolution", resolution}}},
                                                  {"shadow.local_moments", {{"blur_radius", blur}}}};
    if (vsm) params["shadow.local_plan"]["moments"] = 2;
    const ref::LocalComparison c = compare(ref::spot_boxes_scene(), ref::kSpotBoxesEye, params, &pass_ms);
    const std::string row =
        "local.res" + std::to_string(resolution) + "_blur" + std::to_string(blur) + (vsm ? "_vsm" : "");
    table() << std::left << std::setw(8) << (std::to_string(resolution) + (vsm ? " VSM" : "")) << std::setw(8) << blur
            << std::right << std::fixed << std::setprecision(2) << std::setw(10) << pass_ms["map"] << std::setw(12)
            << pass_ms["moments"] << std::setprecision(4) << std::setw(12) << 1.0 - c.share() << std::setw(12)
            << c.mean_error() << std::defaultfloat << "\n";
    figure(row + ".map_ms", pass_ms["map"]);
    figure(row + ".moments_ms", pass_ms["moments"]);
    figure(row + ".disagree", 1.0 - c.share());
    figure(row + ".mean_error", c.mean_error());
  }
}

}  // namespace nightcap::bench
