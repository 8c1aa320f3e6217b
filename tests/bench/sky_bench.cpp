// The sky's LUTs and cube maps: time against error for the transmittance LUT's size and samples,
// sky.view's steps and size, sky.aerial_perspective's size and steps, and sky.specular's samples, each against the
// double-precision references of tests/reference/sky_reference.h and ibl_reference.h.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <iomanip>
#include <random>
#include <string>
#include <vector>

#include "passes/core/history_name.h"
#include "passes/sky/atmosphere.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/stage.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/ibl_reference.h"
#include "tests/reference/sky_reference.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {
namespace {

using glm::dvec3;

constexpr int kTimedRuns = 5;

IsolatedInput lut_input(uint32_t w, uint32_t h, std::vector<uint8_t> bytes) {
  return image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::sky_lut, w, h, std::move(bytes));
}

// A cube map of `side` texels a face and `mips` mips holding `bytes` (zeros when empty).
IsolatedInput cube_input(VkFormat format, uint32_t side, uint32_t mips, std::vector<uint8_t> bytes) {
  const ImageExtent extent{side, side, 1, mips, 6};
  if (bytes.empty()) bytes.resize(raw_image_bytes(*format_info(format), extent));
  IsolatedInput input = image(format, kinds::sky_cube, side, side, std::move(bytes));
  input.desc.extent = extent;
  input.desc.cube = true;
  return input;
}

struct Timed {
  IsolatedRun run;
  double ms = 0;  // median of kTimedRuns after one that creates the pipeline
};

Timed run_timed(GpuDevice& gpu, PipelineCache& cache, const PassDecl& pass,
                const std::map<std::string, IsolatedInput>& inputs, const ParamValues& params) {
  Timed timed{run_isolated(gpu, cache, pass, inputs, params, 1, 1, builtin_shaders()), 0};
  std::vector<double> times;
  for (int k = 0; k < kTimedRuns; ++k)
    times.push_back(
        run_isolated(gpu, cache, pass, inputs, params, 1, 1, builtin_shaders()).execution.passes.at(0).time_ms);
  timed.ms = median(times);
  return timed;
}

struct Row {
  std::string key, label;
  double ms = 0, error = 0, mean = 0;
};

// Marks each row whose (ms, error) no other row beats in both; by the mean error with `by_mean`.
std::vector<bool> pareto_front(const std::vector<Row>& rows, bool by_mean) {
  const auto error = [&](const Row& row) { return by_mean ? row.mean : row.error; };
  std::vector<bool> front;
  for (const Row& row : rows)
    front.push_back(std::none_of(rows.begin(), rows.end(), [&](const Row& other) {
      return other.ms <= row.ms && error(other) <= error(row) && (other.ms < row.ms || error(other) < error(row));
    }));
  return front;
}

// `error` names the error column's figure (its heading, with spaces for underscores); the front is
// by that error, or by the mean with `front_by_mean`.
void print_rows(const std::string& title, const std::string& prefix, const std::vector<Row>& rows,
                const std::string& default_key, bool with_mean, std::string error = "max_rel_err",
                bool front_by_mean = false) {
  const std::vector<bool> front = pareto_front(rows, front_by_mean);
  std::string heading = error;
  std::replace(heading.begin(), heading.end(), '_', ' ');
  table() << "\n## " << title << "\n"
          << std::left << std::setw(16) << "setting" << std::right << std::setw(10) << "ms" << std::setw(14)
          << (with_mean ? "mean rel err" : "") << std::setw(14) << heading << std::setw(8) << "front\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    table() << std::left << std::setw(16) << (row.label + (row.key == default_key ? " *" : "")) << std::right
            << std::fixed << std::setprecision(3) << std::setw(10) << row.ms << std::scientific << std::setprecision(2)
            << std::setw(14);
    if (with_mean)
      table() << row.mean;
    else
      table() << "";
    table() << std::setw(14) << row.error << std::setw(7) << (front[i] ? "yes" : "") << std::defaultfloat << "\n";
    figure(prefix + row.key + ".ms", row.ms);
    figure(prefix + row.key + "." + error, row.error);
    if (with_mean) figure(prefix + row.key + ".mean_rel_err", row.mean);
    figure(prefix + row.key + ".pareto", front[i] ? 1 : 0);
  }
  table() << "(* the default" << (front_by_mean ? "; front: by the mean error" : "") << ")\n";
}

}  // namespace

// sky.transmittance, against adaptive quadrature, the largest relative error where the
// transmittance is at least 2^-14: for each size the LUT read as the sky's passes read it
// (bilinear, at the parameterisation's uv) at 2 000 random heights and directions above the
// horizon; for each sample count, what every third texel stores. sky.view: 252 texels
// (light 10° up, camera 1.7 m up) against a 512-step ray march using the GPU's multiple
// scattering LUT.
void bench_sky(GpuDevice& gpu, PipelineCache& cache) {
  GpuAtmosphere atmosphere = earth_atmosphere({});
  atmosphere.changed = glm::uvec4(1u, 1u, 0u, 0u);
  atmosphere.light.w = 1.7f;  // sky.view's camera, 1.7 m up as the references
  const IsolatedInput atmosphere_in = record_input(atmosphere);
  const ref::Model model(atmosphere);

  struct Point {
    double r, mu;
    dvec3 expected;
  };
  std::vector<Point> points;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  while (points.size() < 2000) {
    const double h = (model.top - model.ground) * unit(rng) * unit(rng), r = model.ground + h;
    const double mu = unit(rng) * 2 - 1;
    if (model.meets_ground(r, mu)) continue;
    points.push_back({r, mu, ref::transmittance_reference(model, r, mu)});
  }
  const auto transmittance_error = [&](const std::vector<uint8_t>& lut, uint32_t w, uint32_t h) {
    double worst = 0;
    for (const Point& p : points) {
      const glm::dvec2 uv = ref::transmittance_uv(model, p.r, p.mu, w, h);
      const dvec3 got = ref::bilinear(lut, w, h, uv.x, uv.y);
      for (int c = 0; c < 3; ++c)
        if (p.expected[c] >= 0x1p-14) worst = std::max(worst, std::abs(got[c] - p.expected[c]) / p.expected[c]);
    }
    return worst;
  };
  const PassDecl transmittance = sky_transmittance_pass();
  const auto run_transmittance = [&](uint32_t w, uint32_t h, uint32_t samples) {
    return run_timed(gpu, cache, transmittance,
                     {{"sky.atmosphere", atmosphere_in},
                      {previous("sky.transmittance"), lut_input(w, h, std::vector<uint8_t>(size_t(w) * h * 8, 0))}},
                     {{"width", double(w)}, {"height", double(h)}, {"samples", double(samples)}});
  };
  std::vector<Row> rows;
  for (const auto& [w, h] : std::vector<std::pair<uint32_t, uint32_t>>{{64, 16}, {128, 32}, {256, 64}, {512, 128}}) {
    const Timed t = run_transmittance(w, h, 256);
    rows.push_back({std::to_string(w) + "x" + std::to_string(h), std::to_string(w) + "x" + std::to_string(h), t.ms,
                    transmittance_error(*t.run.outputs.at("sky.transmittance"), w, h)});
  }
  print_rows("sky.transmittance: size (256 samples) against error at 2 000 random points", "sky.transmittance.size_",
             rows, "256x64", false);
  // Samples decide how exact each texel is, whatever the interpolation between texels does.
  std::vector<std::pair<uint32_t, dvec3>> centres;  // every third texel's index and reference
  for (uint32_t i = 0; i < 256 * 64; i += 3) {
    double r, mu;
    ref::transmittance_r_mu(model, (i % 256 + 0.5) / 256, (i / 256 + 0.5) / 64, 256, 64, r, mu);
    centres.push_back({i, ref::transmittance_reference(model, r, mu)});
  }
  rows.clear();
  for (uint32_t samples : {16u, 32u, 64u, 128u, 256u, 512u}) {
    const Timed t = run_transmittance(256, 64, samples);
    const std::vector<uint8_t>& lut = *t.run.outputs.at("sky.transmittance");
    double worst = 0;
    for (const auto& [i, expected] : centres) {
      const dvec3 got = ref::texel_of(lut, 256, i % 256, i / 256);
      for (int c = 0; c < 3; ++c)
        if (expected[c] >= 0x1p-14) worst = std::max(worst, std::abs(got[c] - expected[c]) / expected[c]);
    }
    rows.push_back({std::to_string(samples), std::to_string(samples) + " samples", t.ms, worst});
  }
  print_rows("sky.transmittance: samples (256x64) against error at every third texel's centre",
             "sky.transmittance.samples_", rows, "256", false);

  // sky.view against the reference, its inputs the default LUTs.
  const Timed lut = run_transmittance(256, 64, 256);
  const std::vector<uint8_t>& transmittance_bytes = *lut.run.outputs.at("sky.transmittance");
  const IsolatedRun ms_run =
      run_isolated(gpu, cache, sky_multiscattering_pass(),
                   {{"sky.atmosphere", atmosphere_in},
                    {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
                    {previous("sky.multiscattering"), lut_input(32, 32, std::vector<uint8_t>(32 * 32 * 8, 0))}},
                   {}, 1, 1, builtin_shaders());
  const std::vector<uint8_t>& ms = *ms_run.outputs.at("sky.multiscattering");

  // sky.multiscattering's size, directions and steps: 40 random heights (denser low, where the
  // sky's rays spend their steps) and light angles outside the planet's shadow against Ψ in double
  // (64×64 directions, 256 steps a ray, the transmittance toward the light from a 512×128 table of
  // adaptive quadratures: tests/reference/sky_reference.h), each LUT read bilinearly as sky.view
  // reads it. Mean: the relative L1 error; largest: over the values at least a tenth of the
  // brightest (relative errors near the shadow's edge divide by nearly nothing).
  {
    struct MsPoint {
      double h, mu;
      dvec3 expected;
    };
    const ref::TransmittanceTable toward_light(model, 512, 128);
    std::vector<MsPoint> ms_points;
    while (ms_points.size() < 40) {
      const double h = (model.top - model.ground) * unit(rng) * unit(rng), mu = unit(rng) * 2 - 1;
      const dvec3 expected =
          ref::multiple_scattering_reference(model, toward_light, h, mu, atmosphere.radii.w, 64, 256);
      if (std::min({expected.x, expected.y, expected.z}) < 1e-6) continue;  // the planet's shadow
      ms_points.push_back({h, mu, expected});
    }
    double brightest = 0;
    for (const MsPoint& p : ms_points) brightest = std::max({brightest, p.expected.x, p.expected.y, p.expected.z});
    rows.clear();
    struct MsSetting {
      uint32_t side, directions, samples;
    };
    for (const auto& [side, directions, samples] :
         std::vector<MsSetting>{{16, 16, 20}, {32, 8, 20}, {32, 16, 20}, {64, 16, 20}, {32, 16, 40}, {32, 32, 20}}) {
      const Timed t = run_timed(
          gpu, cache, sky_multiscattering_pass(),
          {{"sky.atmosphere", atmosphere_in},
           {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
           {previous("sky.multiscattering"), lut_input(side, side, std::vector<uint8_t>(size_t(side) * side * 8, 0))}},
          {{"width", double(side)},
           {"height", double(side)},
           {"directions", double(directions)},
           {"samples", double(samples)}});
      const std::vector<uint8_t>& table = *t.run.outputs.at("sky.multiscattering");
      double error_sum = 0, expected_sum = 0, worst = 0;
      for (const MsPoint& p : ms_points) {
        const dvec3 got = ref::bilinear(table, side, side, ref::texel_coordinate(p.mu * 0.5 + 0.5, side),
                                        ref::texel_coordinate(p.h / (model.top - model.ground), side));
        for (int c = 0; c < 3; ++c) {
          const double error = std::abs(got[c] - p.expected[c]);
          error_sum += error;
          expected_sum += p.expected[c];
          if (p.expected[c] >= 0.1 * brightest) worst = std::max(worst, error / p.expected[c]);
        }
      }
      const std::string key = std::to_string(side) + "x" + std::to_string(side) + "_directions_" +
                              std::to_string(directions) + "_steps_" + std::to_string(samples);
      rows.push_back({key, key, t.ms, worst, error_sum / expected_sum});
    }
    print_rows(
        "sky.multiscattering: size, directions a side and steps against a 64x64-direction double reference at 40 "
        "random points, read bilinearly (mean: relative L1; largest: where at least a tenth of the brightest)",
        "sky.multiscattering.", rows, "32x32_directions_16_steps_20", true);
  }
  GpuFrameConstants frame{};
  const double elevation = glm::radians(10.0);
  const dvec3 to_light(std::cos(elevation) * 0.6, std::sin(elevation), std::cos(elevation) * 0.8);
  frame.sun_direction = glm::vec4(-glm::vec3(to_light), 1.0f);
  frame.sun_radiance = glm::vec4(1.0f);
  frame.camera_world = glm::vec4(0.0f, 1.7f, 0.0f, 1.0f);
  const double r = model.ground + 1.7e-3;
  const dvec3 light(std::sqrt(1 - to_light.y * to_light.y), to_light.y, 0.0);
  struct Texel {
    uint32_t x, y;
    dvec3 expected;
  };
  std::vector<Texel> texels;
  for (uint32_t y = 1; y < 108; y += 7)
    for (uint32_t x = 1; x < 192; x += 9)
      texels.push_back(
          {x, y,
           ref::sky_radiance(model, ms, 32, 32, r, ref::sky_view_direction(model, x, y, 192, 108, r), light, 512)});
  rows.clear();
  for (uint32_t samples : {8u, 16u, 32u, 64u}) {
    const Timed t = run_timed(gpu, cache, sky_view_pass(),
                              {{"frame.constants", constants_input(frame)},
                               {"sky.atmosphere", atmosphere_in},
                               {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
                               {"sky.multiscattering", lut_input(32, 32, ms)},
                               {previous("sky.view"), lut_input(192, 108, std::vector<uint8_t>(192 * 108 * 8, 0))}},
                              {{"samples", double(samples)}});
    const std::vector<uint8_t>& sky = *t.run.outputs.at("sky.view");
    double sum = 0, worst = 0;
    int count = 0;
    for (const Texel& texel : texels) {
      const dvec3 got = ref::texel_of(sky, 192, texel.x, texel.y);
      for (int c = 0; c < 3; ++c) {
        if (texel.expected[c] < 1e-6) continue;
        const double relative = std::abs(got[c] - texel.expected[c]) / texel.expected[c];
        sum += relative;
        worst = std::max(worst, relative);
        ++count;
      }
    }
    rows.push_back({std::to_string(samples), std::to_string(samples) + " steps", t.ms, worst, sum / count});
  }
  print_rows("sky.view: steps (192x108) against a 512-step double ray march, 252 texels", "sky.view.samples_", rows,
             "32", true);

  // sky.view's size: 600 random directions of the sky above and below the horizon against the
  // same ray march, each LUT read bilinearly at its parameterisation's uv, as the composite and
  // sky.cubemap read it.
  struct Direction {
    dvec3 d, expected;
  };
  std::vector<Direction> directions;
  while (directions.size() < 600) {
    const dvec3 d(unit(rng) * 2 - 1, unit(rng) * 2 - 1, unit(rng));
    if (glm::length(d) > 1 || glm::length(d) < 0.1) continue;
    const dvec3 n = glm::normalize(d);
    const dvec3 expected = ref::sky_radiance(model, ms, 32, 32, r, n, light, 512);
    if (std::min({expected.x, expected.y, expected.z}) < 1e-6) continue;
    directions.push_back({n, expected});
  }
  rows.clear();
  for (const auto& [w, h] : std::vector<std::pair<uint32_t, uint32_t>>{{96, 54}, {192, 108}, {384, 216}}) {
    const Timed t = run_timed(gpu, cache, sky_view_pass(),
                              {{"frame.constants", constants_input(frame)},
                               {"sky.atmosphere", atmosphere_in},
                               {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
                               {"sky.multiscattering", lut_input(32, 32, ms)},
                               {previous("sky.view"), lut_input(w, h, std::vector<uint8_t>(size_t(w) * h * 8, 0))}},
                              {{"width", double(w)}, {"height", double(h)}});
    const std::vector<uint8_t>& sky = *t.run.outputs.at("sky.view");
    double sum = 0, worst = 0;
    for (const Direction& dir : directions) {
      const glm::dvec2 uv = ref::sky_view_uv(model, dir.d, r, w, h);
      const dvec3 got = ref::bilinear(sky, w, h, uv.x, uv.y);
      for (int c = 0; c < 3; ++c) {
        const double relative = std::abs(got[c] - dir.expected[c]) / dir.expected[c];
        sum += relative;
        worst = std::max(worst, relative);
      }
    }
    const std::string key = std::to_string(w) + "x" + std::to_string(h);
    rows.push_back({key, key, t.ms, worst, sum / (3.0 * directions.size())});
  }
  print_rows("sky.view: size (32 steps) against a 512-step double ray march at 600 random directions, read bilinearly",
             "sky.view.size_", rows, "192x108", true);

  // sky.aerial_perspective's size and steps: 400 random points of a street camera's view (1.7 m
  // up, looking 10° down, 70° across) at distances from 10 m to 30 km short of the ground, whose
  // in-scattering is in half floats' normal range, against a 256-step double march along the same
  // ray, the volume read as the composite reads it (trilinear, the nearest points a share of the
  // first slice).
  {
    const glm::mat4 view_matrix =
        glm::lookAt(glm::vec3(0.0f), glm::vec3(std::cos(0.17f), -std::sin(0.17f), 0.4f), glm::vec3(0.0f, 1.0f, 0.0f));
    const glm::mat4 inverse_view_projection =
        glm::inverse(glm::perspective(glm::radians(70.0f), 16.0f / 9.0f, 0.1f, 1000.0f) * view_matrix);
    GpuView camera{};
    camera.inverse_view_projection = inverse_view_projection;
    GpuFrameConstants lit = frame;
    struct AirPoint {
      glm::dvec2 uv;
      double distance_km;
      dvec3 in_scattered;
      double transmittance;
    };
    std::vector<AirPoint> air_points;
    constexpr double kRadiance = 10.0;  // the light's, of the order of the frame's sun
    lit.sun_radiance = glm::vec4(float(kRadiance));
    while (air_points.size() < 400) {
      const glm::dvec2 uv(unit(rng), unit(rng));
      const double distance_km = 0.01 * std::pow(3000.0, unit(rng));
      const glm::dvec4 far_point = glm::dmat4(inverse_view_projection) * glm::dvec4(uv * 2.0 - 1.0, 1.0, 1.0);
      const dvec3 direction = glm::normalize(dvec3(far_point) / far_point.w);
      if (distance_km > ref::ground_distance(model, r, direction.y)) continue;  // no point beyond the ground
      ref::AirMarch march(model, ms, 32, 32, r, direction, to_light, 256);
      for (int i = 0; i < 256; ++i) march.step(distance_km * i / 256, distance_km * (i + 1) / 256);
      // Where half floats hold the radiance to their precision (their normal range).
      if (std::min({march.radiance.x, march.radiance.y, march.radiance.z}) * kRadiance < 0x1p-14) continue;
      air_points.push_back(
          {uv, distance_km, march.radiance * kRadiance, glm::dot(march.transmittance, dvec3(1.0 / 3))});
    }
    rows.clear();
    struct Setting {
      uint32_t side, slices, samples;
    };
    for (const Setting& setting :
         std::vector<Setting>{{16, 16, 1}, {32, 32, 1}, {32, 32, 2}, {32, 32, 4}, {64, 64, 1}, {32, 64, 1}}) {
      const Timed t = run_timed(gpu, cache, sky_aerial_perspective_pass(),
                                {{"frame.constants", constants_input(lit)},
                                 {"frame.views", record_input(camera)},
                                 {"sky.atmosphere", atmosphere_in},
                                 {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
                                 {"sky.multiscattering", lut_input(32, 32, ms)}},
                                {{"width", double(setting.side)},
                                 {"height", double(setting.side)},
                                 {"slices", double(setting.slices)},
                                 {"samples", double(setting.samples)}});
      const std::vector<uint8_t>& volume = *t.run.outputs.at("sky.aerial_perspective");
      double sum = 0, worst = 0;
      for (const AirPoint& p : air_points) {
        const ref::Air air =
            ref::aerial_perspective(volume, setting.side, setting.side, setting.slices, p.uv, p.distance_km);
        for (int c = 0; c < 3; ++c) {
          const double relative = std::abs(air.in_scattered[c] - p.in_scattered[c]) / p.in_scattered[c];
          sum += relative;
          worst = std::max(worst, relative);
        }
      }
      const std::string key = std::to_string(setting.side) + "x" + std::to_string(setting.side) + "x" +
                              std::to_string(setting.slices) + "_steps_" + std::to_string(setting.samples);
      rows.push_back({key, key, t.ms, worst, sum / (3.0 * air_points.size())});
    }
    print_rows(
        "sky.aerial_perspective: size and steps a slice against a 256-step double ray march at 400 random points "
        "from 10 m to 30 km, read trilinearly",
        "sky.aerial_perspective.", rows, "32x32x32_steps_1", true, "max_rel_err", true);
  }

  // sky.specular against the split sum's prefilter from 65536 samples in double (every third
  // texel across and down of each mip), on the sky cube of the same sky: for each sample count
  // the largest over the mips of the RMSE over the reference's RMS.
  const IsolatedRun view =
      run_isolated(gpu, cache, sky_view_pass(),
                   {{"frame.constants", constants_input(frame)},
                    {"sky.atmosphere", atmosphere_in},
                    {"sky.transmittance", lut_input(256, 64, transmittance_bytes)},
                    {"sky.multiscattering", lut_input(32, 32, ms)},
                    {previous("sky.view"), lut_input(192, 108, std::vector<uint8_t>(192 * 108 * 8, 0))}},
                   {}, 1, 1, builtin_shaders());
  const IsolatedRun cube_run =
      run_isolated(gpu, cache, sky_cubemap_pass(),
                   {{"frame.constants", constants_input(frame)},
                    {"sky.atmosphere", atmosphere_in},
                    {"sky.view", lut_input(192, 108, *view.outputs.at("sky.view"))},
                    {previous("sky.cubemap"), cube_input(VK_FORMAT_B10G11R11_UFLOAT_PACK32, 128, 8, {})}},
                   {}, 1, 1, builtin_shaders());
  const std::vector<uint8_t>& cube = *cube_run.outputs.at("sky.cubemap");
  const ImageExtent cube_extent = cube_run.output_descs.at("sky.cubemap").extent;
  const IsolatedInput cube_in =
      cube_input(VK_FORMAT_B10G11R11_UFLOAT_PACK32, cube_extent.width, cube_extent.mips, cube);
  const IsolatedInput no_specular = cube_input(VK_FORMAT_R16G16B16A16_SFLOAT, 64, kSkySpecularMips, {});
  const ref::CubeLevel source =
      ref::cube_level(cube, VK_FORMAT_B10G11R11_UFLOAT_PACK32, cube_extent.width, cube_extent.mips, 0);
  struct Probe {
    uint32_t mip, index;  // index: face-major, rows down, in the mip
    dvec3 expected;
  };
  std::vector<Probe> probes;
  constexpr uint32_t specular_side = 64;
  for (uint32_t mip = 1; mip < kSkySpecularMips; ++mip) {
    const uint32_t side = mip_size(specular_side, mip);
    const double roughness = double(mip) / (kSkySpecularMips - 1);
    for (uint32_t face = 0; face < 6; ++face)
      for (uint32_t y = 0; y < side; y += 3)
        for (uint32_t x = 0; x < side; x += 3)
          probes.push_back({mip, (face * side + y) * side + x,
                            ref::prefiltered(source, ref::texel_direction(face, x, y, side), roughness, 65536)});
  }
  rows.clear();
  for (uint32_t samples : {16u, 32u, 64u, 128u, 255u}) {
    const Timed t = run_timed(
        gpu, cache, sky_specular_pass(),
        {{"sky.atmosphere", atmosphere_in}, {"sky.cubemap", cube_in}, {previous("sky.specular"), no_specular}},
        {{"samples", double(samples)}});
    const std::vector<uint8_t>& bytes = *t.run.outputs.at("sky.specular");
    std::vector<double> squares(kSkySpecularMips, 0), signal(kSkySpecularMips, 0);
    std::vector<ref::CubeLevel> levels;
    for (uint32_t mip = 0; mip < kSkySpecularMips; ++mip)
      levels.push_back(ref::cube_level(bytes, VK_FORMAT_R16G16B16A16_SFLOAT, specular_side, kSkySpecularMips, mip));
    for (const Probe& p : probes) {
      const dvec3 error = levels[p.mip].texels[p.index] - p.expected;
      squares[p.mip] += glm::dot(error, error);
      signal[p.mip] += glm::dot(p.expected, p.expected);
    }
    double worst = 0;
    for (uint32_t mip = 1; mip < kSkySpecularMips; ++mip)
      worst = std::max(worst, std::sqrt(squares[mip] / signal[mip]));
    rows.push_back({std::to_string(samples), std::to_string(samples) + " samples", t.ms, worst});
  }
  print_rows(
      "sky.specular: samples at mip 1 (4x more each mip down) against a 65536-sample double prefilter, "
      "worst mip",
      "sky.specular.samples_", rows, "128", false, "rmse");
}

}  // namespace nightcap::bench
