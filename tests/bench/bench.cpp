// nightcap's benchmark: prints figures, asserts nothing.
//  - per-pass GPU time (median over repeats) for the built-in city and the glTF models;
//  - frame time with capture off and on, and their ratio, in the same run;
//  - capture bytes on disk against the raw sum of recorded resources, and per extra frame of a
//    still and of a walking camera;
//  - the frame's GPU memory with transient resources aliased and without (peak_gpu_mib,
//    peak_gpu_mib_no_aliasing: the built-in city);
//  - scene.geometry's position bits against their error in mm, its size against float vertices;
//  - time against error for each pass knob (normals.pack LUT size, lighting.deferred tube samples
//    against the CPU segment integral, depth.convert (full and half resolution), depth.pyramid,
//    motion.stencil (time against its dilation radius) and bloom against their references);
//  - the CLI's start-up: `nightcap --help` and `nightcap passes` of a city capture, wall clock;
//    the debugger's first answer and its export of gbuffer.opaque's colour targets;
//  - `nightcap diff` of a 1280x720 pair against idiff over the same images;
//  - lights.cluster + lighting.tiled against lighting.deferred (tiled), with extra lights;
//  - lighting.tiled's tube quality: LTC table size and nodes per line, time against error;
//  - lights.cluster's froxel shape (cluster_shape): tile size and slice count, time against the
//    error of lighting.tiled against lighting.deferred;
//  - LTC tube and sphere lights (ltc): error against the integral of GGX by table size,
//    roughness and view angle, fit time, and the CPU time of one light.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "passes/core/device.h"
#include "passes/core/pipeline_cache.h"
#include "passes/scene/scene.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;
namespace fs = std::filesystem;
using namespace nightcap::bench;

int main(int argc, char** argv) {
  CLI::App app{"nightcap benchmark: per-pass GPU time, capture cost and size, time against error"};
  uint32_t repeats = 5, directions = 1 << 20;
  std::string size = "1280x720", device, data = NIGHTCAP_SHARED_DATA;
  bool skip_models = false, map_frames = true;
  std::vector<std::string> only;
  const std::vector<std::string> sections = {"city",
                                             "models",
                                             "map",
                                             "empty",
                                             "frames",
                                             "normals",
                                             "tubes",
                                             "depth",
                                             "motion",
                                             "streams",
                                             "bloom",
                                             "exposure",
                                             "startup",
                                             "diff",
                                             "report",
                                             "decals",
                                             "ltc",
                                             "cluster",
                                             "tiled",
                                             "tube_quality",
                                             "cluster_shape",
                                             "shadows",
                                             "tod",
                                             "distant",
                                             "shadow_cache",
                                             "local",
                                             "pass_times",
                                             "sky",
                                             "sky_ibl",
                                             "probes",
                                             "probe_tradeoffs",
                                             "topdown",
                                             "gi",
                                             "taa",
                                             "ao"};
  app.add_option("--repeats", repeats, "frames per measurement (medians are reported)")->capture_default_str();
  app.add_option("--size", size, "output size WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--device", device, "Vulkan device name (substring); default: lavapipe");
  app.add_option("--directions", directions, "directions for the normals.pack error sweep")->capture_default_str();
  app.add_option("--data", data, "shared/data folder with the glTF models")->capture_default_str();
  app.add_flag("!--no-map-frames", map_frames,
               "the map section measures cull.main only (its frames take minutes: every light in view is shaded "
               "at every pixel until clustered lighting)");
  app.add_flag("--skip-models", skip_models, "leave out the glTF models (the models section)");
  app.add_option("--only", only, "run only these sections (repeatable)")->check(CLI::IsMember(sections));
  app.add_flag("--json", g_json, "print {\"figures\": {NAME: NUMBER}} on stdout (the tables go to stderr)");
  CLI11_PARSE(app, argc, argv);
  uint32_t width = 1280, height = 720;
  if (std::sscanf(size.c_str(), "%ux%u", &width, &height) != 2 || width == 0 || height == 0) {
    std::cerr << "--size '" << size << "': expected WIDTHxHEIGHT\n";
    return 2;
  }
  try {
    nc::GpuDevice gpu({device, false});
    nc::PipelineCache cache(gpu);
    table() << "# nightcap benchmark on " << gpu.name() << " (" << gpu.driver() << ")\n";
    auto wanted = [&](const std::string& section) {
      return only.empty() ? !(section == "models" && skip_models)
                          : std::find(only.begin(), only.end(), section) != only.end();
    };
    if (wanted("city"))
      bench_scene(gpu, "city", "built-in city (seed 1)", nc::build_city(1), width, height, int(repeats), true);
    if (wanted("models")) {
      for (const auto& entry : fs::directory_iterator(fs::path(data) / "gltf")) {
        const fs::path file = entry.path() / "glTF" / (entry.path().filename().string() + ".gltf");
        const std::string model = entry.path().filename().string();
        if (fs::exists(file))
          bench_scene(gpu, model, model, nc::load_gltf(file.string()), width, height, int(repeats), false);
      }
    }
    if (wanted("map")) bench_map(gpu, cache, width, height, int(repeats), map_frames);
    if (wanted("empty")) bench_empty(gpu, width, height, int(repeats));
    if (wanted("frames")) bench_extra_frames(gpu, width, height);
    if (wanted("normals")) bench_normals(gpu, cache, directions);
    if (wanted("tubes")) bench_tube_samples(gpu, width / 2, height / 2);
    if (wanted("depth")) bench_depth(gpu, cache, width, height);
    if (wanted("motion")) bench_motion_stencil(gpu, cache, width, height);
    if (wanted("streams")) {
      bench_vertex_streams("city", "built-in city (seed 1)", nc::build_city(1));
      const fs::path helmet = fs::path(data) / "gltf/DamagedHelmet/glTF/DamagedHelmet.gltf";
      if (!skip_models && fs::exists(helmet))
        bench_vertex_streams("DamagedHelmet", "DamagedHelmet", nc::load_gltf(helmet.string()));
    }
    if (wanted("bloom")) bench_bloom(gpu, cache, width, height);
    if (wanted("exposure")) bench_exposure(gpu, cache, width, height);
    if (wanted("startup")) bench_startup(gpu, width, height);
    if (wanted("diff")) bench_diff(gpu, width, height);
    if (wanted("report")) bench_report(gpu, width, height);
    if (wanted("decals")) bench_decals(gpu, width, height, int(repeats));
    if (wanted("ltc")) bench_ltc();
    if (wanted("cluster")) bench_cluster(gpu, cache, width, height, int(repeats));
    if (wanted("tiled")) bench_tiled(gpu, cache, width, height, int(repeats));
    if (wanted("tube_quality")) bench_tube_quality(gpu, width, height);
    if (wanted("cluster_shape")) bench_cluster_shape(gpu, cache, width, height, int(repeats));
    if (wanted("shadows")) bench_shadows(gpu, width, height, int(repeats));
    if (wanted("tod")) bench_tod(gpu, width, height, int(repeats));
    if (wanted("distant")) bench_distant(gpu, width, height);
    if (wanted("shadow_cache")) {
      bench_shadow_cache(gpu, width, height, int(repeats));
      bench_cascade_budget(gpu, width, height);
    }
    if (wanted("local")) bench_local(gpu, width, height, int(repeats));
    if (wanted("pass_times")) bench_pass_times(gpu, width, height, 3);
    if (wanted("sky")) bench_sky(gpu, cache);
    if (wanted("sky_ibl")) bench_sky_ibl_cost(gpu, width, height, int(repeats));
    if (wanted("probes")) bench_probes(gpu, width, height, int(repeats));
    if (wanted("probe_tradeoffs")) bench_probe_tradeoffs(gpu, cache, width, height);
    if (wanted("topdown")) bench_topdown(gpu, width, height, int(repeats));
    if (wanted("gi")) bench_gi(gpu, width, height, int(repeats));
    if (wanted("taa")) bench_taa(gpu, width, height, int(repeats));
    if (wanted("ao")) bench_ao(gpu, width, height, int(repeats));
    if (g_json) std::cout << nlohmann::json{{"figures", g_figures}}.dump(1) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "nightcap_bench: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
