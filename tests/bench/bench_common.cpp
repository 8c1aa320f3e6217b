// What the benchmarks share: the figures sink, medians and the clock, passes' times and inputs, spot lights in view.
#include "tests/bench/bench_common.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <utility>

#include <glm/gtc/packing.hpp>

namespace nc = nightcap;

namespace nightcap::bench {

bool g_json = false;
std::map<std::string, double> g_figures;

std::ostream& table() { return g_json ? std::cerr : std::cout; }

void figure(const std::string& name, double value) { g_figures[name] = value; }

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

nc::IsolatedInput image(VkFormat format, nc::ResourceKind kind, uint32_t w, uint32_t h, std::vector<uint8_t> bytes) {
  nc::IsolatedInput in;
  in.desc.format = format;
  in.desc.kind = kind;
  in.desc.extent.width = w;
  in.desc.extent.height = h;
  in.bytes = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
  return in;
}

nc::IsolatedInput constants_input(const nc::GpuFrameConstants& constants) { return nc::record_input(constants); }

double gpu_ms(const nc::IsolatedRun& run) { return run.execution.passes.at(0).gpu_ms.value_or(0.0); }

double frame_pass_ms(const nc::RenderedFrame& frame, const std::string& pass) {
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass && frame.graph.passes[i].runs) {
      return frame.execution.passes[i].time_ms;
    }
  return 0.0;
}

void add_spots_in_view(nc::Scene& scene, uint32_t width, uint32_t height, int count) {
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  const nc::Camera camera = nc::base_camera(scene, settings);
  const glm::dvec3 eye = glm::dvec3(camera.world[3]);
  const double tan_x = std::tan(camera.yfov / 2) * width / height;
  std::mt19937 rng{uint32_t(count)};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const double depth = 10.0 + 50.0 * unit(rng);
    const glm::dvec3 local((unit(rng) * 2 - 1) * tan_x * depth * 0.8, 0.0, -depth);
    nc::Light spot;
    spot.type = nc::LightType::spot;
    spot.position = eye + glm::dvec3(camera.world * glm::dvec4(local, 0.0));
    spot.position.y = 8.0;
    spot.direction = glm::normalize(glm::vec3(glm::dvec3(camera.world * glm::dvec4(0.0, 0.0, -0.3, 0.0))) +
                                    glm::vec3(0.0f, -1.0f, 0.0f));
    spot.intensity = 2000.0f;
    spot.range = 25.0f;
    spot.inner_cone = 0.4f;
    spot.outer_cone = 0.7f;
    scene.lights.push_back(spot);
  }
}

OnOffMedians alternate_frames(GpuDevice& gpu, const Scene& scene, const RenderSettings& on, const RenderSettings& off,
                              int repeats) {
  Renderer with(gpu, scene, on), without(gpu, scene, off);
  with.render_frame(0, false);
  without.render_frame(0, false);
  std::vector<double> on_ms, off_ms;
  for (int r = 1; r <= repeats; ++r)
    for (const bool feature : {r % 2 == 1, r % 2 == 0}) {
      const double start = now_ms();
      (feature ? with : without).render_frame(uint32_t(r), false);
      (feature ? on_ms : off_ms).push_back(now_ms() - start);
    }
  return {median(on_ms), median(off_ms)};
}

void street_on_off(GpuDevice& gpu, const Scene& scene, uint32_t width, uint32_t height, int repeats,
                   const std::string& group, const std::string& ratio_figure, const std::string& key) {
  RenderSettings on;
  on.width = width;
  on.height = height;
  on.pass_timing = PassTiming::overlapped;
  RenderSettings off = on;
  off.params[group]["enabled"] = 0.0;
  const OnOffMedians cost = alternate_frames(gpu, scene, on, off, repeats);
  table() << "on " << std::fixed << std::setprecision(1) << cost.on_ms << " ms, off " << cost.off_ms << " ms, ratio "
          << std::setprecision(3) << cost.ratio() << "\n";
  figure(ratio_figure, cost.ratio());
  figure("frame_ms_street_" + key + "_on", cost.on_ms);
  figure("frame_ms_street_" + key + "_off", cost.off_ms);
}

RenderSettings still_street_settings() {
  RenderSettings settings;
  settings.width = 640;
  settings.height = 360;
  settings.pass_timing.reset();
  return settings;
}

double rgba16f_rms_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, uint64_t texels) {
  double squares = 0;
  for (uint64_t t = 0; t < texels; ++t) {
    uint16_t x[3], y[3];
    std::memcpy(x, a.data() + t * 8, sizeof x);
    std::memcpy(y, b.data() + t * 8, sizeof y);
    for (int c = 0; c < 3; ++c) {
      const double d = double(glm::unpackHalf1x16(x[c])) - double(glm::unpackHalf1x16(y[c]));
      squares += d * d;
    }
  }
  return std::sqrt(squares / double(texels));
}

}  // namespace nightcap::bench
