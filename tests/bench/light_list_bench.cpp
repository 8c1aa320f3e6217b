// Light lists: lights.cluster, lights.cluster + lighting.tiled against lighting.deferred, and the froxel shape.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/frame/gpu_types.h"
#include "passes/lighting/stage.h"
#include "passes/lights/cluster_layout.h"
#include "passes/lights/stage.h"
#include "passes/scene/scene.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/unit/recorded_pass.h"

namespace nc = nightcap;

namespace nightcap::bench {

namespace {

// `count` point lights of 10 m range spread uniformly over the part of the view within 200 m of
// the camera of frame 0 (by volume: distance ∝ the cube root of a uniform draw), seeded.
void add_lights_in_view(nc::Scene& scene, uint32_t width, uint32_t height, int count) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  const nc::Camera camera = nc::base_camera(scene, settings);
  const glm::dvec3 eye = glm::dvec3(camera.world[3]);
  const double tan_y = std::tan(camera.yfov / 2), tan_x = tan_y * width / height;
  std::mt19937 rng{uint32_t(count)};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    // A point of the pyramid of the view up to 200 m ahead: depth by volume, then across it.
    const double depth = 200.0 * std::cbrt(unit(rng));
    const glm::dvec3 local((unit(rng) * 2 - 1) * tan_x * depth, (unit(rng) * 2 - 1) * tan_y * depth, -depth);
    nc::Light light;
    light.position = eye + glm::dvec3(camera.world * glm::dvec4(local, 0.0));
    light.color = {float(unit(rng)), float(unit(rng)), float(unit(rng))};
    light.intensity = 100.0f;
    light.range = 10.0f;
    scene.lights.push_back(light);
  }
}

// The mean length of the froxel list lighting.tiled reads per shaded pixel (drawn and not
// emission-only), from its recorded inputs: the slice of the pixel's linear depth by the shape
// lights.cluster recorded (cluster_layout.h's formula: a pixel on a slice bound may land one
// slice off the shader's, which moves the mean by nothing visible).
double mean_list_per_pixel(const std::map<std::string, nc::IsolatedInput>& inputs, const nc::GpuClusterStats& stats) {
  nc::GpuView camera;
  std::memcpy(&camera, inputs.at("frame.views").bytes->data(), sizeof camera);
  const nc::IsolatedInput& clusters = inputs.at("lights.clusters");
  const auto& linear = *inputs.at("depth.linear").bytes;
  const auto& depth = *inputs.at("scene.depth").bytes;
  const auto& albedo = *inputs.at("gbuffer.albedo").bytes;
  const nc::ImageExtent size = inputs.at("gbuffer.albedo").desc.extent, tiles = clusters.desc.extent;
  double entries = 0;
  size_t pixels = 0;
  for (uint32_t y = 0; y < size.height; ++y)
    for (uint32_t x = 0; x < size.width; ++x) {
      const size_t t = size_t(y) * size.width + x;
      float device_depth, metres;
      uint32_t albedo_word;
      std::memcpy(&device_depth, depth.data() + 4 * t, 4);
      std::memcpy(&albedo_word, albedo.data() + 4 * t, 4);
      std::memcpy(&metres, linear.data() + 4 * t, 4);
      if (device_depth <= 0 || (albedo_word >> 30) != 0) continue;
      const uint32_t slice = nc::cluster_slice(metres, camera.projection_params.x, stats.max_distance, stats.slices);
      const size_t froxel = (size_t(slice) * tiles.height + y / stats.tile_size) * tiles.width + x / stats.tile_size;
      uint32_t count;
      std::memcpy(&count, clusters.bytes->data() + 8 * froxel + 4, 4);
      entries += count;
      ++pixels;
    }
  return pixels ? entries / double(pixels) : 0.0;
}

}  // namespace

// lights.cluster on the street shot of a 2 km map, of the 16 km map (the built-in scene: thousands
// of lights survive the frame's culling there) and on the built-in city, each frame rendered
// only as far as the clusters (the map's lighting.deferred shades every light at every pixel and
// takes minutes at 1280x720 on lavapipe): GPU time in the frame (timestamps, median of `repeats`
// walking frames after a warm-up one), the isolated run's wall clock on the last frame's recorded
// inputs (upload and readback included: an upper bound, lavapipe's timestamps undercount
// compute), and the mean list length over the froxels that have one.
void bench_cluster(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## lights.cluster (" << width << "x" << height << ", median of " << repeats << ")\n";
  nc::Scene city = nc::build_city(1);
  nc::add_default_lighting(city);
  const std::vector<std::pair<std::string, nc::Scene>> scenes = {
      {"map_street", nc::build_map({1, 2.0, nc::Shot::street})},
      {"map16_street", nc::build_map({1, 16.0, nc::Shot::street})},
      {"city", std::move(city)}};
  for (const auto& [key, scene] : scenes) {
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.sinks = {"lights.clusters", "lights.cluster_indices", "lights.cluster_stats"};
    nc::Renderer renderer(gpu, scene, settings);
    renderer.render_frame(0, false);
    std::vector<double> ms;
    for (int r = 1; r <= repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
      for (size_t i = 0; i < frame.graph.passes.size(); ++i)
        if (frame.graph.passes[i].decl->name == "lights.cluster" && frame.graph.passes[i].runs)
          ms.push_back(frame.execution.passes[i].time_ms);
    }
    const nc::RenderedFrame captured = renderer.render_frame(uint32_t(repeats) + 1, true);
    std::map<std::string, nc::IsolatedInput> inputs;
    for (const char* name : {"frame.constants", "frame.views", "frame.lights", "depth.pyramid"}) {
      const nc::VersionData* v = captured.execution.final_version(name);
      inputs[name] = {v->desc, v->bytes};
    }
    const nc::PassDecl pass = nc::lights_cluster_pass();
    std::vector<double> wall;
    for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
      const double start = now_ms();
      nc::run_isolated(gpu, cache, pass, inputs, pass.default_params(), width, height, nc::builtin_shaders());
      if (r > 0) wall.push_back(now_ms() - start);
    }
    nc::GpuClusterStats stats{};
    std::memcpy(&stats, captured.execution.final_version("lights.cluster_stats")->bytes->data(), sizeof(stats));
    const double mean = stats.froxels_lit ? double(stats.entries) / stats.froxels_lit : 0.0;
    table() << std::left << std::setw(14) << key << std::right << std::fixed << std::setprecision(3) << median(ms)
            << " ms (timestamps), " << median(wall) << " ms isolated wall clock; " << stats.lights << " local lights, "
            << stats.froxels_lit << " of " << stats.froxels << " froxels lit, mean list " << std::setprecision(2)
            << mean << ", longest " << stats.max_count << ", " << stats.entries << " entries\n";
    const std::string suffix = key == "map_street" ? "" : "." + key;
    figure("cluster_ms" + suffix, median(ms));
    figure("cluster_isolated_wall_ms" + suffix, median(wall));
    figure("lights_per_froxel_mean" + suffix, mean);
  }
}

// lights.cluster + lighting.tiled against lighting.deferred on the same frame (frame 0, the same
// lights), GPU time by timestamps, frames rendered only as far as lighting: the 2 km map's street
// shot and the built-in city, each as it is and with 100 and 1 000 more lights of 10 m range in
// the first 200 m of the view. Tiled: median of `repeats` frames; deferred: one frame (on the map
// it takes seconds a frame on lavapipe). Then the same passes each run alone on that frame's
// recorded inputs, wall clock (upload and readback included; tiled the median of 3 runs after a
// warm-up one, deferred one run): lavapipe's timestamps around a compute pass can take in work
// queued before it, so this ratio (`…_isolated`) does not depend on them.
void bench_tiled(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## lighting.tiled against lighting.deferred (" << width << "x" << height << ", GPU ms)\n"
          << std::left << std::setw(18) << "scene" << std::right << std::setw(8) << "lights" << std::setw(12)
          << "cluster" << std::setw(12) << "tiled" << std::setw(12) << "deferred" << std::setw(10) << "ratio"
          << "\n";
  for (const std::string key : {"map_street", "city"}) {
    for (int extra : {0, 100, 1000}) {
      nc::Scene scene = key == "city" ? nc::build_city(1) : nc::build_map({1, 2.0, nc::Shot::street});
      nc::add_default_lighting(scene);
      add_lights_in_view(scene, width, height, extra);
      nc::RenderSettings settings;
      settings.width = width;
      settings.height = height;
      settings.sinks = {"lighting.diffuse", "lighting.specular"};
      std::vector<double> cluster, tiled;
      uint32_t lights = 0;
      // A pass alone on the frame's recorded inputs: the median wall clock of `runs` after a warm-up one.
      auto isolated_ms = [&](const nc::PassDecl& pass, const nc::RenderedFrame& frame, int runs) {
        const std::map<std::string, nc::IsolatedInput> inputs = nc::recorded_pass(frame, pass.name).inputs;
        std::vector<double> wall;
        for (int r = 0; r <= runs; ++r) {
          const double start = now_ms();
          nc::run_isolated(gpu, cache, pass, inputs, pass.default_params(), width, height, nc::builtin_shaders());
          if (r > 0 || runs == 0) wall.push_back(now_ms() - start);
        }
        return median(wall);
      };
      double cluster_alone = 0, tiled_alone = 0;
      {
        nc::Renderer renderer(gpu, scene, settings);
        for (int r = 0; r < repeats; ++r) {
          const nc::RenderedFrame frame = renderer.render_frame(0, false);
          cluster.push_back(frame_pass_ms(frame, "lights.cluster"));
          tiled.push_back(frame_pass_ms(frame, "lighting.tiled"));
        }
        const nc::RenderedFrame captured = renderer.render_frame(0, true);
        nc::GpuFrameConstants constants;
        std::memcpy(&constants, captured.execution.final_version("frame.constants")->bytes->data(), sizeof constants);
        lights = constants.counts.x;
        cluster_alone = isolated_ms(nc::lights_cluster_pass(), captured, 3);
        tiled_alone = isolated_ms(nc::lighting_tiled_pass(), captured, 3);
      }
      settings.lighting = nc::FrameLighting::deferred;
      nc::Renderer renderer(gpu, scene, settings);
      const nc::RenderedFrame deferred_frame = renderer.render_frame(0, true);
      const double deferred = frame_pass_ms(deferred_frame, "lighting.deferred");
      const double deferred_alone = isolated_ms(nc::lighting_deferred_pass(), deferred_frame, 0);
      const double ratio = (median(cluster) + median(tiled)) / deferred;
      const double ratio_alone = (cluster_alone + tiled_alone) / deferred_alone;
      table() << std::left << std::setw(18) << key + (extra ? " +" + std::to_string(extra) : "") << std::right
              << std::setw(8) << lights << std::fixed << std::setprecision(1) << std::setw(12) << median(cluster)
              << std::setw(12) << median(tiled) << std::setw(12) << deferred << std::setprecision(4) << std::setw(10)
              << ratio << std::defaultfloat << "\n"
              << std::left << std::setw(18) << "  alone" << std::right << std::setw(8) << "" << std::fixed
              << std::setprecision(1) << std::setw(12) << cluster_alone << std::setw(12) << tiled_alone << std::setw(12)
              << deferred_alone << std::setprecision(4) << std::setw(10) << ratio_alone << std::defaultfloat << "\n";
      // A named count: GCC 12 at -O3 warns (-Wrestrict, a false positive) on "_" + std::to_string(extra) here.
      const std::string added = std::to_string(extra);
      const std::string suffix = (extra ? "_" + added : "") + (key == "city" ? ".city" : "");
      figure("tiled_vs_deferred_ratio" + suffix, ratio);
      figure("tiled_vs_deferred_ratio_isolated" + suffix, ratio_alone);
      figure("tiled_isolated_wall_ms" + suffix, tiled_alone);
      figure("tiled_cluster_isolated_wall_ms" + suffix, cluster_alone);
      figure("deferred_isolated_wall_ms" + suffix, deferred_alone);
      figure("tiled_ms" + suffix, median(tiled));
      figure("tiled_cluster_ms" + suffix, median(cluster));
      figure("deferred_ms" + suffix, deferred);
    }
  }
}

// lights.cluster's froxel shape, time against error: the 2 km map's street shot rendered as far
// as lighting with tiles of 32 px and 16, 32, 64 or 128 slices, and with 64 slices and tiles of
// 16, 32 or 64 px. Time: GPU ms of lights.cluster + lighting.tiled in the frame (timestamps),
// median of `repeats` frames. Load: the mean list over the froxels that have one, the mean list
// lighting.tiled walks per shaded pixel (its froxel's: what a coarser shape adds there is lights
// that do not reach the pixel), and the froxels the caps cut (lights.cluster_stats). Error: lighting.tiled run alone on
// the frame's recorded inputs against lighting.deferred (every light at every pixel) on the same inputs, with spheres
// and tubes dark and no contact shadow: lighting.deferred models area lights otherwise, and for the sun, point and spot
// lights the two passes compute the same bits, so what differs is what the lists miss. Per colour channel of diffuse
// and specular, relative to deferred where it exceeds 2^-14.
//  - cluster_shape.slices<N>.{ms,cluster_ms,tiled_ms,lights_per_froxel,lights_per_pixel,overflow,
//    err_max,err_mean}
//    (tiles of 32 px), and cluster_shape.tile<N>.{…} (64 slices); overflow: froxels over
//    max_lights_per_froxel plus froxels cut at max_indices.
void bench_cluster_shape(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height, int repeats) {
  const nc::Scene scene = nc::build_map({1, 2.0, nc::Shot::street});
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"lighting.diffuse", "lighting.specular"};
  // lighting.deferred has no sun shadow: shadow.sun is then 1 everywhere.
  settings.params["shadow.sun_resolve"]["enabled"] = 0;
  // A lighting pass's recorded inputs with the spheres and tubes (frame.lights from
  // light_groups.y on) dark.
  auto without_area_lights = [](std::map<std::string, nc::IsolatedInput> inputs) {
    nc::GpuFrameConstants constants;
    std::memcpy(&constants, inputs.at("frame.constants").bytes->data(), sizeof constants);
    auto lights = std::make_shared<std::vector<uint8_t>>(*inputs.at("frame.lights").bytes);
    for (uint32_t i = constants.light_groups.y; i < constants.counts.x; ++i) {
      nc::GpuLight light;
      std::memcpy(&light, lights->data() + i * sizeof light, sizeof light);
      light.color_range = glm::vec4(0, 0, 0, light.color_range.w);
      std::memcpy(lights->data() + i * sizeof light, &light, sizeof light);
    }
    inputs["frame.lights"].bytes = lights;
    return inputs;
  };
  nc::ParamValues no_contact = nc::lighting_tiled_pass().default_params();
  no_contact["contact_steps"] = 0;
  const nc::FormatInfo half = *nc::format_info(VK_FORMAT_R16G16B16A16_SFLOAT);

  // The baseline: the G-buffer does not depend on the froxels, so one deferred run serves all.
  nc::IsolatedRun deferred;
  {
    nc::Renderer renderer(gpu, scene, settings);
    const nc::RenderedFrame frame = renderer.render_frame(0, true);
    deferred = nc::run_isolated(gpu, cache, nc::lighting_deferred_pass(),
                                without_area_lights(nc::recorded_pass(frame, "lighting.tiled").inputs),
                                nc::lighting_deferred_pass().default_params(), width, height, nc::builtin_shaders());
  }
  table() << "\n## lights.cluster froxel shape, time against error (2 km map, street shot, " << width << "x" << height
          << ", GPU ms median of " << repeats << "; error against lighting.deferred, deferred " << std::fixed
          << std::setprecision(0) << gpu_ms(deferred) << " ms)\n"
          << std::left << std::setw(8) << "tile" << std::setw(8) << "slices" << std::right << std::setw(10) << "ms"
          << std::setw(10) << "cluster" << std::setw(10) << "tiled" << std::setw(14) << "lights/froxel" << std::setw(13)
          << "lights/pixel" << std::setw(10) << "overflow" << std::setw(12) << "max rel" << std::setw(12) << "mean rel"
          << std::defaultfloat << "\n";
  struct Shape {
    uint32_t tile, slices;
    std::string row;
  };
  std::vector<Shape> shapes;
  for (uint32_t slices : {16u, 32u, 64u, 128u}) shapes.push_back({32, slices, "slices" + std::to_string(slices)});
  for (uint32_t tile : {16u, 32u, 64u}) shapes.push_back({tile, 64, "tile" + std::to_string(tile)});
  for (const Shape& shape : shapes) {
    settings.params["lights.cluster"] = {{"tile_size", shape.tile}, {"slices", shape.slices}};
    nc::Renderer renderer(gpu, scene, settings);
    const nc::RenderedFrame captured = renderer.render_frame(0, true);  // compiles the pipelines too
    std::vector<double> cluster, tiled, both;
    for (int r = 0; r < repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(0, false);
      cluster.push_back(frame_pass_ms(frame, "lights.cluster"));
      tiled.push_back(frame_pass_ms(frame, "lighting.tiled"));
      both.push_back(cluster.back() + tiled.back());
    }
    nc::GpuClusterStats stats{};
    std::memcpy(&stats, captured.execution.final_version("lights.cluster_stats")->bytes->data(), sizeof(stats));
    const double per_froxel = stats.froxels_lit ? double(stats.entries) / stats.froxels_lit : 0.0;
    const uint32_t overflow = stats.froxels_over_cap + stats.froxels_cut;
    const std::map<std::string, nc::IsolatedInput> inputs = nc::recorded_pass(captured, "lighting.tiled").inputs;
    const double per_pixel = mean_list_per_pixel(inputs, stats);

    const nc::IsolatedRun shaded = nc::run_isolated(gpu, cache, nc::lighting_tiled_pass(), without_area_lights(inputs),
                                                    no_contact, width, height, nc::builtin_shaders());
    double worst = 0, sum = 0;
    size_t values = 0;
    for (const char* output : {"lighting.diffuse", "lighting.specular"}) {
      const auto& got = *shaded.outputs.at(output);
      const auto& want = *deferred.outputs.at(output);
      for (size_t texel = 0; texel < size_t(width) * height; ++texel) {
        float g[4], w[4];
        nc::decode_texel(half, 0, got, texel, g);
        nc::decode_texel(half, 0, want, texel, w);
        for (int c = 0; c < 3; ++c) {
          if (!(w[c] > 0x1p-14f)) continue;
          const double error = std::abs(double(g[c]) - w[c]) / w[c];
          worst = std::max(worst, error);
          sum += error;
          ++values;
        }
      }
    }
    const double mean = values ? sum / double(values) : 0.0;
    table() << std::left << std::setw(8) << shape.tile << std::setw(8) << shape.slices << std::right << std::fixed
            << std::setprecision(1) << std::setw(10) << median(both) << std::setw(10) << median(cluster)
            << std::setw(10) << median(tiled) << std::setprecision(2) << std::setw(14) << per_froxel << std::setw(13)
            << per_pixel << std::setw(10) << overflow << std::scientific << std::setprecision(2) << std::setw(12)
            << worst << std::setw(12) << mean << std::defaultfloat << "\n";
    const std::string row = "cluster_shape." + shape.row;
    figure(row + ".ms", median(both));
    figure(row + ".cluster_ms", median(cluster));
    figure(row + ".tiled_ms", median(tiled));
    figure(row + ".lights_per_froxel", per_froxel);
    figure(row + ".lights_per_pixel", per_pixel);
    figure(row + ".overflow", overflow);
    figure(row + ".err_max", worst);
    figure(row + ".err_mean", mean);
  }
}

}  // namespace nightcap::bench
