// What the benchmarks share: the figures sink, medians and the clock, passes' times and inputs, spot lights in view.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/core/isolated.h"
#include "passes/core/resource_kind.h"
#include "passes/frame/gpu_types.h"
#include "passes/scene/scene.h"

namespace nightcap::bench {

// Tables for a person go to stdout; with --json they go to stderr and stdout carries only
// {"figures": {NAME: NUMBER}}, every number of the tables under a stable name.
extern bool g_json;
extern std::map<std::string, double> g_figures;

std::ostream& table();

void figure(const std::string& name, double value);

double median(std::vector<double> values);

double now_ms();

// An image input of a pass run on its own.
IsolatedInput image(VkFormat format, ResourceKind kind, uint32_t w, uint32_t h, std::vector<uint8_t> bytes);

// frame.constants as an input of a pass run on its own.
IsolatedInput constants_input(const GpuFrameConstants& constants);

// The GPU time of a pass run on its own, by timestamps; 0 without them.
double gpu_ms(const IsolatedRun& run);

// A pass's time in a frame (PassExecution::time_ms: on a CPU device, with the renderer's default
// timing, the pass timed alone); 0 when it did not run.
double frame_pass_ms(const RenderedFrame& frame, const std::string& pass);

// A feature's cost in the whole frame: a renderer with it (`on`) and one without (`off`) on the
// same scene, each warmed up by frame 0, then frames 1..repeats on each in turn so that both see
// the same machine; the medians of each frame's wall clock.
struct OnOffMedians {
  double on_ms = 0, off_ms = 0;
  double ratio() const { return on_ms / off_ms; }
};
OnOffMedians alternate_frames(GpuDevice& gpu, const Scene& scene, const RenderSettings& on, const RenderSettings& off,
                              int repeats);

// The cost of a feature that `--set GROUP.enabled=0` switches off, in the frame frame_ms_street
// measures: `scene` walking at width × height, the passes overlapped, alternate_frames with the
// feature on and off. Prints the table's line and records `ratio_figure` and
// frame_ms_street_<key>_{on,off}.
void street_on_off(GpuDevice& gpu, const Scene& scene, uint32_t width, uint32_t height, int repeats,
                   const std::string& group, const std::string& ratio_figure, const std::string& key);

// The settings of a time-against-error table on the street shot (frozen, still camera): 640×360,
// where the references are measured, each pass timed alone on a CPU device.
RenderSettings still_street_settings();

// The RMS over `texels` of the difference of two RGBA16F images (RGB only).
double rgba16f_rms_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, uint64_t texels);

// `count` spot lights 8 m up, pointing down and ahead, 25 m range, spread over the first 60 m of
// the view of frame 0 (seeded): street lamps over the part of the scene the maps cover.
void add_spots_in_view(Scene& scene, uint32_t width, uint32_t height, int count);

}  // namespace nightcap::bench
