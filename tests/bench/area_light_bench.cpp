// Tube and sphere lights, time against error: lighting.deferred's tube samples, lighting.tiled's tubes, LTC tables.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/frame/gpu_types.h"
#include "passes/lighting/ltc/fit.h"
#include "passes/lighting/ltc/ltc.h"
#include "passes/lighting/stage.h"
#include "passes/scene/scene.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/lighting_reference.h"
#include "tests/reference/ltc_reference.h"
#include "tests/unit/recorded_pass.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {

// lighting.deferred: tube-light diffuse samples against the CPU integral along each segment
// (tests/reference/lighting_reference.h), on a G-buffer of the built-in city with only its tube
// lights left (no sun, no point or spot lights), at every 4th pixel in x and y.
void bench_tube_samples(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  nc::Scene scene = nc::build_city(1);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.lighting = nc::FrameLighting::deferred;
  nc::Renderer renderer(gpu, scene, settings);
  const nc::RenderedFrame frame = renderer.render_frame(0, true);
  std::map<std::string, nc::IsolatedInput> inputs = nc::recorded_pass(frame, "lighting.deferred").inputs;
  nc::GpuFrameConstants constants;
  std::memcpy(&constants, inputs.at("frame.constants").bytes->data(), sizeof(constants));
  nc::GpuView camera;
  std::memcpy(&camera, inputs.at("frame.views").bytes->data(), sizeof(camera));
  const auto& light_bytes = *inputs.at("frame.lights").bytes;
  std::vector<nc::GpuLight> tubes;
  for (size_t offset = 0; offset + sizeof(nc::GpuLight) <= light_bytes.size(); offset += sizeof(nc::GpuLight)) {
    nc::GpuLight light;
    std::memcpy(&light, light_bytes.data() + offset, sizeof(light));
    if (uint32_t(light.position_type.w) == uint32_t(nc::LightType::tube)) tubes.push_back(light);
  }
  if (tubes.empty()) {
    table() << "\n## lighting.deferred: the built-in city has no tube lights\n";
    return;
  }
  constants.sun_direction.w = 0;
  constants.counts.x = uint32_t(tubes.size());
  auto replace = [&](const std::string& name, const void* data, size_t size) {
    auto bytes = std::make_shared<std::vector<uint8_t>>(size);
    std::memcpy(bytes->data(), data, size);
    inputs[name].bytes = bytes;
    inputs[name].desc.buffer_size = size;
  };
  replace("frame.constants", &constants, sizeof(constants));
  replace("frame.lights", tubes.data(), tubes.size() * sizeof(nc::GpuLight));

  const nc::ParamValues defaults = nc::lighting_deferred_pass().default_params();
  const double scale = defaults.at("intensity_scale"), min_roughness = float(defaults.at("min_roughness"));
  const auto& albedo = *inputs.at("gbuffer.albedo").bytes;
  const auto& normal = *inputs.at("gbuffer.normal").bytes;
  const auto& material = *inputs.at("gbuffer.material").bytes;
  const auto& depth = *inputs.at("scene.depth").bytes;
  struct Sample {
    size_t texel;
    glm::dvec3 diffuse;
  };
  std::vector<Sample> samples;
  const double cpu_start = now_ms();
  for (uint32_t y = 0; y < height; y += 4)
    for (uint32_t x = 0; x < width; x += 4) {
      const size_t t = size_t(y) * width + x;
      uint32_t albedo_word, normal_word;
      float device_depth;
      std::memcpy(&albedo_word, albedo.data() + 4 * t, 4);
      std::memcpy(&normal_word, normal.data() + 4 * t, 4);
      std::memcpy(&device_depth, depth.data() + 4 * t, 4);
      if (device_depth <= 0 || (albedo_word >> 30) != 0) continue;  // sky or unlit: not shaded
      const ref::Surface s = ref::make_surface(ref::reconstruct_position(camera, x, y, device_depth), normal_word,
                                               albedo_word, material.data() + 4 * t, min_roughness);
      Sample sample{t, glm::dvec3(0.0)};
      for (const nc::GpuLight& tube : tubes) sample.diffuse += ref::Tube(s, tube, scale).diffuse();
      samples.push_back(sample);
    }
  const double cpu_ms = now_ms() - cpu_start;

  nc::PipelineCache cache(gpu);
  const nc::FormatInfo half = *nc::format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  table() << "\n## lighting.deferred: tube diffuse samples vs the CPU segment integral (built-in city, " << width << "x"
          << height << ", " << tubes.size() << " tube lights, " << samples.size() << " pixels, reference " << std::fixed
          << std::setprecision(0) << cpu_ms << " ms on the CPU)\n"
          << std::left << std::setw(12) << "samples" << std::right << std::setw(12) << "gpu ms" << std::setw(16)
          << "mean rel err" << std::setw(14) << "max rel err"
          << "\n";
  for (double count : {1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 256.0}) {
    nc::ParamValues params = defaults;
    params["tube_samples"] = count;
    std::vector<double> times;
    nc::IsolatedRun result;
    for (int r = 0; r < 3; ++r) {
      result = nc::run_isolated(gpu, cache, nc::lighting_deferred_pass(), inputs, params, width, height,
                                nc::builtin_shaders());
      times.push_back(gpu_ms(result));
    }
    const auto& out = *result.outputs.at("lighting.diffuse");
    double sum = 0, worst = 0;
    size_t counted = 0;
    for (const Sample& sample : samples) {
      float x[4];
      nc::decode_texel(half, 0, out, sample.texel, x);
      for (int c = 0; c < 3; ++c) {
        if (sample.diffuse[c] < 1e-3) continue;  // relative error of near-black texels says nothing
        const double e = std::abs(x[c] - sample.diffuse[c]) / sample.diffuse[c];
        sum += e;
        worst = std::max(worst, e);
        ++counted;
      }
    }
    table() << std::left << std::setw(12) << int(count) << std::right << std::fixed << std::setprecision(3)
            << std::setw(12) << median(times) << std::scientific << std::setprecision(2) << std::setw(16)
            << sum / std::max<size_t>(counted, 1) << std::setw(14) << worst << std::defaultfloat << "\n";
    const std::string row = "tube_samples_" + std::to_string(int(count));
    figure(row + ".gpu_ms", median(times));
    figure(row + ".mean_rel_err", sum / std::max<size_t>(counted, 1));
    figure(row + ".max_rel_err", worst);
  }
}

// Tube-light quality in lighting.tiled, time against error: the built-in city's tubes alone (as
// lighting_tiled_test.cpp's tube test: lines, everything else dark) through the LTC table of 16,
// 32 (fitted here) and 64 entries a side (committed) and 2, 4, 8 or 16 Gauss-Legendre nodes per
// line (tube_nodes), against the CPU integral of GGX and of Lambert along each segment at every
// 12th pixel of every 12th row. GPU ms of the pass alone on the recorded inputs, median of 3.
//  - tube_quality.<size>_<nodes>.gpu_ms, .specular_err (error weighted by the reference over
//    views ≤ 80°), .diffuse_err (the same for the diffuse part).
void bench_tube_quality(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  nc::Scene scene = nc::build_city(1);
  nc::add_default_lighting(scene);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"lighting.diffuse", "lighting.specular"};
  nc::Renderer renderer(gpu, scene, settings);
  const nc::RenderedFrame frame = renderer.render_frame(0, true);
  std::map<std::string, nc::IsolatedInput> inputs = nc::recorded_pass(frame, "lighting.tiled").inputs;
  nc::GpuFrameConstants constants;
  std::memcpy(&constants, inputs.at("frame.constants").bytes->data(), sizeof(constants));
  nc::GpuView camera;
  std::memcpy(&camera, inputs.at("frame.views").bytes->data(), sizeof(camera));
  std::vector<nc::GpuLight> lights(constants.counts.x);
  std::memcpy(lights.data(), inputs.at("frame.lights").bytes->data(), lights.size() * sizeof(nc::GpuLight));
  size_t tubes = 0;
  for (nc::GpuLight& light : lights) {
    if (uint32_t(light.position_type.w) == uint32_t(nc::LightType::tube)) {
      light.end_radius.w = 0;  // a line, as the reference integrates
      ++tubes;
    } else {
      light.color_range = glm::vec4(0, 0, 0, light.color_range.w);
    }
  }
  constants.sun_direction.w = 0;
  auto replace = [&](const std::string& name, const void* data, size_t size) {
    auto bytes = std::make_shared<std::vector<uint8_t>>(size);
    std::memcpy(bytes->data(), data, size);
    inputs[name].bytes = bytes;
  };
  replace("frame.constants", &constants, sizeof(constants));
  replace("frame.lights", lights.data(), lights.size() * sizeof(nc::GpuLight));

  const nc::ParamValues defaults = nc::lighting_tiled_pass().default_params();
  const double min_roughness = float(defaults.at("min_roughness"));
  const auto& albedo = *inputs.at("gbuffer.albedo").bytes;
  const auto& normal = *inputs.at("gbuffer.normal").bytes;
  const auto& material = *inputs.at("gbuffer.material").bytes;
  const auto& depth = *inputs.at("scene.depth").bytes;
  struct Sample {
    size_t texel;
    glm::dvec3 diffuse, specular;
    bool in_bound;  // view ≤ 80°
  };
  std::vector<Sample> samples;
  for (uint32_t y = 6; y < height; y += 12)
    for (uint32_t x = 6; x < width; x += 12) {
      const size_t t = size_t(y) * width + x;
      uint32_t albedo_word, normal_word;
      float device_depth;
      std::memcpy(&albedo_word, albedo.data() + 4 * t, 4);
      std::memcpy(&normal_word, normal.data() + 4 * t, 4);
      std::memcpy(&device_depth, depth.data() + 4 * t, 4);
      if (device_depth <= 0 || (albedo_word >> 30) != 0) continue;
      const ref::Surface s = ref::make_surface(ref::reconstruct_position(camera, x, y, device_depth), normal_word,
                                               albedo_word, material.data() + 4 * t, min_roughness);
      Sample sample{t, glm::dvec3(0.0), glm::dvec3(0.0), glm::dot(s.n, s.v) >= std::cos(glm::radians(80.0))};
      for (const nc::GpuLight& light : lights) {
        if (uint32_t(light.position_type.w) != uint32_t(nc::LightType::tube)) continue;
        const ref::Tube tube(s, light, 1.0);
        sample.diffuse += tube.diffuse();
        sample.specular += tube.specular();
      }
      samples.push_back(sample);
    }

  struct Sized {
    int size;
    std::shared_ptr<std::vector<uint8_t>> inverse, magnitude;
  };
  std::vector<Sized> tables;
  for (int size : {16, 32, 64}) {
    nc::ltc::Table table;
    if (size == 64) {
      table = nc::ltc::ggx_table();
    } else {
      nc::ltc::FitSettings fit;
      fit.size = size;
      table = nc::ltc::fit_table(fit);
    }
    Sized sized{size, std::make_shared<std::vector<uint8_t>>(size_t(size) * size * 16),
                std::make_shared<std::vector<uint8_t>>(size_t(size) * size * 8)};
    for (size_t i = 0; i < table.entries.size(); ++i) {
      const float magnitudes[2] = {table.entries[i].norm, table.entries[i].fresnel};
      std::memcpy(sized.inverse->data() + 16 * i, table.entries[i].inverse.data(), 16);
      std::memcpy(sized.magnitude->data() + 8 * i, magnitudes, 8);
    }
    tables.push_back(std::move(sized));
  }

  nc::PipelineCache cache(gpu);
  const nc::FormatInfo half = *nc::format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  table() << "\n## lighting.tiled: tube quality, time against error (built-in city, " << width << "x" << height << ", "
          << tubes << " tube lines alone, " << samples.size()
          << " pixels; error weighted by the reference, specular over views <= 80 deg)\n"
          << std::left << std::setw(10) << "table" << std::setw(8) << "nodes" << std::right << std::setw(10) << "gpu ms"
          << std::setw(14) << "specular err" << std::setw(14) << "diffuse err"
          << "\n";
  for (const Sized& sized : tables) {
    inputs["lighting.ltc_inverse"].bytes = sized.inverse;
    inputs["lighting.ltc_inverse"].desc.extent = {uint32_t(sized.size), uint32_t(sized.size), 1, 1, 1};
    inputs["lighting.ltc_magnitude"].bytes = sized.magnitude;
    inputs["lighting.ltc_magnitude"].desc.extent = {uint32_t(sized.size), uint32_t(sized.size), 1, 1, 1};
    for (int nodes : {2, 4, 8, 16}) {
      nc::ParamValues params = defaults;
      params["tube_nodes"] = nodes;
      std::vector<double> times;
      nc::IsolatedRun result;
      for (int r = 0; r < 3; ++r) {
        result = nc::run_isolated(gpu, cache, nc::lighting_tiled_pass(), inputs, params, width, height,
                                  nc::builtin_shaders());
        times.push_back(gpu_ms(result));
      }
      const auto& diffuse_out = *result.outputs.at("lighting.diffuse");
      const auto& specular_out = *result.outputs.at("lighting.specular");
      double specular_error = 0, specular_sum = 0, diffuse_error = 0, diffuse_sum = 0;
      for (const Sample& sample : samples) {
        float d[4], sp[4];
        nc::decode_texel(half, 0, diffuse_out, sample.texel, d);
        nc::decode_texel(half, 0, specular_out, sample.texel, sp);
        for (int c = 0; c < 3; ++c) {
          diffuse_error += std::abs(d[c] - std::min(sample.diffuse[c], 65504.0));
          diffuse_sum += sample.diffuse[c];
          if (!sample.in_bound) continue;
          specular_error += std::abs(sp[c] - std::min(sample.specular[c], 65504.0));
          specular_sum += sample.specular[c];
        }
      }
      const double specular = specular_error / specular_sum, diffuse = diffuse_error / diffuse_sum;
      table() << std::left << std::setw(10) << sized.size << std::setw(8) << nodes << std::right << std::fixed
              << std::setprecision(1) << std::setw(10) << median(times) << std::setprecision(4) << std::setw(14)
              << specular << std::setw(14) << diffuse << std::defaultfloat << "\n";
      const std::string row = "tube_quality." + std::to_string(sized.size) + "_" + std::to_string(nodes);
      figure(row + ".gpu_ms", median(times));
      figure(row + ".specular_err", specular);
      figure(row + ".diffuse_err", diffuse);
    }
  }
}

// ltc: tube and sphere lights through LTC tables (passes/lighting/ltc) against the integral of
// GGX along the segment and over the cap (tests/reference/ltc_reference.h: accuracy.md's cases,
// 85° views added): tables of 16 and 32 entries per axis fitted here, timed, and the committed
// one; for the committed table, the error by roughness and view, what weighing Fresnel as the
// lobe's average (the table's fresnel) instead of per direction would cost, and the CPU time of
// one light; the error of the line integral's 8-node quadrature against 64 nodes.
void bench_ltc() {
  const std::vector<double> roughnesses{0.05, 0.1, 0.25, 0.5, 0.75, 1.0};
  const std::vector<double> views{0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 85};
  const std::vector<ref::TubeCase> tubes = ref::tube_cases(roughnesses, views);
  const std::vector<ref::SphereCase> spheres = ref::sphere_cases(roughnesses, views);
  std::vector<double> tube_exact, sphere_exact;
  for (const ref::TubeCase& c : tubes) tube_exact.push_back(ref::reference_specular(c));
  for (const ref::SphereCase& c : spheres) sphere_exact.push_back(ref::reference_sphere_specular(c, 300));

  struct Sized {
    nc::ltc::Table table;
    double fit_s;
  };
  std::vector<Sized> tables;
  for (int size : {16, 32}) {
    nc::ltc::FitSettings settings;
    settings.size = size;
    const double start = now_ms();
    nc::ltc::Table table = nc::ltc::fit_table(settings);
    tables.push_back({std::move(table), (now_ms() - start) / 1e3});
  }
  tables.push_back({nc::ltc::ggx_table(), 0});

  // Mean and max relative error over views ≤ 80° and max at 85°, of `error(i)` over `count` cases.
  struct Errors {
    double mean = 0, max = 0, max_85 = 0;
  };
  auto summarise = [](size_t count, const auto& view_of, const auto& error) {
    Errors e;
    size_t counted = 0;
    for (size_t i = 0; i < count; ++i) {
      const double x = error(i);
      if (view_of(i) <= 80) {
        e.mean += x;
        e.max = std::max(e.max, x);
        ++counted;
      } else {
        e.max_85 = std::max(e.max_85, x);
      }
    }
    e.mean /= double(std::max<size_t>(counted, 1));
    return e;
  };
  auto tube_errors = [&](const nc::ltc::Table& t) {
    return summarise(
        tubes.size(), [&](size_t i) { return tubes[i].view_degrees; },
        [&](size_t i) { return std::abs(ref::ltc_specular(t, tubes[i]) / tube_exact[i] - 1); });
  };
  auto sphere_errors = [&](const nc::ltc::Table& t) {
    return summarise(
        spheres.size(), [&](size_t i) { return spheres[i].view_degrees; },
        [&](size_t i) { return std::abs(ref::ltc_sphere_specular(t, spheres[i]) / sphere_exact[i] - 1); });
  };

  table() << "\n## ltc: specular vs the integral of GGX (" << tubes.size() << " tubes and " << spheres.size()
          << " spheres: 6 roughnesses, views 0-85°, 3 sizes, f0 0.04 and 1)\n"
          << std::left << std::setw(8) << "size" << std::right << std::setw(8) << "fit s" << std::setw(14)
          << "tube mean" << std::setw(12) << "tube max" << std::setw(12) << "max 85°" << std::setw(14) << "sphere mean"
          << std::setw(12) << "sphere max" << std::setw(12) << "max 85°"
          << "  (mean and max over views ≤ 80°)\n";
  for (const Sized& sized : tables) {
    const bool committed = &sized == &tables.back();
    const Errors tube = tube_errors(sized.table), sphere = sphere_errors(sized.table);
    const std::string size = std::to_string(sized.table.size);
    table() << std::left << std::setw(8) << (size + (committed ? "*" : "")) << std::right << std::fixed
            << std::setprecision(1) << std::setw(8) << sized.fit_s << std::setprecision(2) << std::setw(13)
            << 100 * tube.mean << "%" << std::setw(11) << 100 * tube.max << "%" << std::setw(11) << 100 * tube.max_85
            << "%" << std::setw(13) << 100 * sphere.mean << "%" << std::setw(11) << 100 * sphere.max << "%"
            << std::setw(11) << 100 * sphere.max_85 << "%" << std::defaultfloat << "\n";
    figure("ltc_tube_error_mean." + size, tube.mean);
    figure("ltc_tube_error_max." + size, tube.max);
    figure("ltc_tube_error_max_85deg." + size, tube.max_85);
    figure("ltc_sphere_error_mean." + size, sphere.mean);
    figure("ltc_sphere_error_max." + size, sphere.max);
    if (!committed) figure("ltc_fit_s." + size, sized.fit_s);
    if (committed) {
      figure("ltc_tube_error_mean", tube.mean);
      figure("ltc_tube_error_max", tube.max);
      figure("ltc_sphere_error_mean", sphere.mean);
      figure("ltc_sphere_error_max", sphere.max);
    }
  }
  table() << "* committed (passes/lighting/ltc/ggx_table.h)\n";

  // The committed table, cell by cell: max (and mean) over the cell's sizes, orientations and f0.
  const nc::ltc::Table& committed = nc::ltc::ggx_table();
  std::map<std::pair<double, double>, std::pair<double, int>> tube_mean, sphere_mean;
  std::map<std::pair<double, double>, double> tube_max, sphere_max;
  for (size_t i = 0; i < tubes.size(); ++i) {
    const double e = std::abs(ref::ltc_specular(committed, tubes[i]) / tube_exact[i] - 1);
    const std::pair<double, double> cell{tubes[i].roughness, tubes[i].view_degrees};
    tube_max[cell] = std::max(tube_max[cell], e);
    tube_mean[cell].first += e;
    ++tube_mean[cell].second;
  }
  for (size_t i = 0; i < spheres.size(); ++i) {
    const double e = std::abs(ref::ltc_sphere_specular(committed, spheres[i]) / sphere_exact[i] - 1);
    const std::pair<double, double> cell{spheres[i].roughness, spheres[i].view_degrees};
    sphere_max[cell] = std::max(sphere_max[cell], e);
    sphere_mean[cell].first += e;
    ++sphere_mean[cell].second;
  }
  auto print_cells = [&](const std::string& title, const auto& value) {
    table() << "\n"
            << title << ", committed table, roughness × view (°)\n"
            << std::left << std::setw(6) << "r" << std::right;
    for (double view : views) table() << std::setw(7) << int(view);
    table() << "\n";
    for (double r : roughnesses) {
      table() << std::left << std::fixed << std::setprecision(2) << std::setw(6) << r << std::right
              << std::setprecision(1);
      for (double view : views) table() << std::setw(6) << 100 * value(std::make_pair(r, view)) << "%";
      table() << std::defaultfloat << "\n";
    }
  };
  print_cells("tube: max relative error", [&](const auto& cell) { return tube_max[cell]; });
  print_cells("tube: mean relative error",
              [&](const auto& cell) { return tube_mean[cell].first / tube_mean[cell].second; });
  print_cells("sphere: max relative error", [&](const auto& cell) { return sphere_max[cell]; });

  // Fresnel as the lobe's average, f0·norm + (1 − f0)·fresnel, on the same integrals of D.
  const Errors tube_average = summarise(
      tubes.size(), [&](size_t i) { return tubes[i].view_degrees; },
      [&](size_t i) {
        const ref::TubeCase& c = tubes[i];
        const nc::ltc::Lobe lobe = nc::ltc::lookup(committed, c.roughness, c.v.z);
        const double d = nc::ltc::line_integral(lobe.minv, c.v, c.end1, c.end2).x;
        return std::abs(lobe.magnitude(c.f0) * d / tube_exact[i] - 1);
      });
  const Errors sphere_average = summarise(
      spheres.size(), [&](size_t i) { return spheres[i].view_degrees; },
      [&](size_t i) {
        const ref::SphereCase& c = spheres[i];
        const nc::ltc::Lobe lobe = nc::ltc::lookup(committed, c.roughness, c.v.z);
        const double d = nc::ltc::sphere_integral(lobe, c.v, c.centre, c.radius).x / lobe.norm;
        return std::abs(lobe.magnitude(c.f0) * d / sphere_exact[i] - 1);
      });
  table() << "\nFresnel as the lobe's average instead of per direction: tube mean " << std::fixed
          << std::setprecision(2) << 100 * tube_average.mean << "%, max " << 100 * tube_average.max << "%; sphere mean "
          << 100 * sphere_average.mean << "%, max " << 100 * sphere_average.max << "%\n"
          << std::defaultfloat;
  figure("ltc_tube_error_max_lobe_fresnel", tube_average.max);
  figure("ltc_sphere_error_max_lobe_fresnel", sphere_average.max);

  // The CPU cost of one light: frame, lookup, the lines (specular and Lambert) or the polygon.
  const int repeats = 200;
  double checksum = 0;
  double start = now_ms();
  for (int r = 0; r < repeats; ++r)
    for (const ref::TubeCase& c : tubes) checksum += ref::ltc_specular(committed, c);
  const double tube_us = (now_ms() - start) * 1e3 / (double(repeats) * tubes.size());
  start = now_ms();
  for (int r = 0; r < repeats; ++r)
    for (const ref::SphereCase& c : spheres) checksum += ref::ltc_sphere_specular(committed, c);
  const double sphere_us = (now_ms() - start) * 1e3 / (double(repeats) * spheres.size());
  double quadrature = 0;
  for (const ref::TubeCase& c : tubes) {
    const nc::ltc::Lobe lobe = nc::ltc::lookup(committed, c.roughness, c.v.z);
    const glm::dvec2 coarse = nc::ltc::line_integral(lobe.minv, c.v, c.end1, c.end2);
    const glm::dvec2 fine = nc::ltc::line_integral(lobe.minv, c.v, c.end1, c.end2, 64);
    // The Fresnel part vanishes where h meets v: measured against the plain integral.
    quadrature = std::max({quadrature, std::abs(coarse.x - fine.x) / fine.x, std::abs(coarse.y - fine.y) / fine.x});
  }
  table() << "one light on the CPU: tube " << std::setprecision(3) << tube_us << " µs, sphere " << sphere_us
          << " µs; the tube's 8-node quadrature against 64 nodes: max " << std::scientific << std::setprecision(2)
          << quadrature << std::defaultfloat << " relative (checksum " << checksum << ")\n";
  figure("ltc_tube_eval_us", tube_us);
  figure("ltc_sphere_eval_us", sphere_us);
  figure("ltc_line_quadrature_max_rel", quadrature);
}

}  // namespace nightcap::bench
