// Renders frames of a scene through the render graph, optionally into a capture.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "captures/capture.h"
#include "passes/assembly/frame_passes.h"
#include "passes/core/executor.h"
#include "passes/core/history.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"

namespace nightcap {

// How the camera moves from frame to frame: along its view at a walker's or a car's speed
// (metres per second; scene units are metres), and which frames cut to another view.
struct CameraPath {
  enum class Motion { still, walk, drive } motion = Motion::walk;
  std::set<uint32_t> cuts;  // frames that start from another view: every history resets
  // In place of the motion's speed (a stress test's camera jumping 100 m a frame).
  std::optional<double> speed_override;

  static Motion parse_motion(const std::string& name);  // "static", "walk", "drive"; throws SceneError
  static std::string motion_name(Motion motion);
  double speed() const;  // 0, 1.4 or 14 m/s, or speed_override
  bool cut_at(uint32_t frame) const { return cuts.count(frame) != 0; }
};

// `--inject-nan PASS:X,Y`: a NaN in PASS's first float colour output (in declaration order),
// at the texel under output pixel (X, Y), written after PASS runs in every frame.
struct NanRequest {
  std::string text;  // as given, for messages
  std::string pass;
  uint32_t x = 0, y = 0;
};

struct RenderSettings {
  uint32_t width = 1280, height = 720;
  uint32_t frames = 1;
  uint32_t first_recorded = 0, last_recorded = UINT32_MAX;  // --record-frames A..B; others only render
  CameraPath path;
  ParamOverrides params;           // --set (passes/core/params.h)
  std::optional<Camera> camera;    // --orbit; else the scene's, else a framing one
  nlohmann::json description;      // settings as given, recorded in the manifest
  CaptureWriter::Options capture;  // blob codecs
  bool alias_memory = true;        // ExecutionOptions::alias_memory
  std::vector<NanRequest> inject_nan;
  // What the frame must produce; empty: frame_sinks(). Fewer sinks run part of the frame (a
  // benchmark or test of the passes before lighting).
  std::vector<std::string> sinks;
  // Resources whose last version each frame copies to the host besides final.ldr (a test or a
  // benchmark reading one image without capturing the frame).
  std::set<std::string> readback;
  FrameLighting lighting = FrameLighting::tiled;  // deferred: the baseline a benchmark compares with
  // How pass times are measured; unset: default_pass_timing of the device (alone on a CPU).
  std::optional<PassTiming> pass_timing;
};

// Parses "PASS:X,Y"; throws SceneError naming the flag.
NanRequest parse_inject_nan(const std::string& text);
// Throws SceneError naming the flag for a pass that no pass declares, one named twice, or a
// pixel outside the output.
void validate_nan_requests(const std::vector<PassDecl>& passes, const std::vector<NanRequest>& requests, uint32_t width,
                           uint32_t height);

// Adds a key light when a scene with meshes has none, as glTF viewers do (recorded in
// scene.notes).
void add_default_lighting(Scene& scene);

// The camera of frame k: after the n-th cut the base view turned n quarter turns about the
// vertical axis through the scene's centre (for a street, the next street; for an orbit, the
// next side), moved along its view at the path's speed for the time since that cut.
Camera frame_camera(const Camera& base, const Scene& scene, const CameraPath& path, uint32_t frame);
Camera base_camera(const Scene& scene, const RenderSettings& settings);

struct RenderedFrame {
  CompiledGraph graph;
  Execution execution;
  Camera camera;
  double time = 0;  // seconds since frame 0
  // What passes' warn_from checks said of this frame ("lights.cluster: …"), also printed on stderr.
  std::vector<std::string> warnings;
};

class Renderer {
 public:
  // The frame of frame_passes(settings.lighting), with the built-in shaders.
  Renderer(GpuDevice& gpu, const Scene& scene, RenderSettings settings);
  // Another assembly of passes (add_scene_passes and the rest, with passes of its own between
  // them), whose shaders `shaders` supplies.
  Renderer(GpuDevice& gpu, const Scene& scene, RenderSettings settings, std::vector<PassDecl> passes,
           ShaderProvider shaders);
  // Frame `index`, reading the history the previous render_frame left (render them in order).
  // With `capture`, every version is read back; a `writer` starts encoding each one as soon as
  // it reaches the host, while the rest of the frame runs (record_frame completes the record),
  // or, when passes are timed alone, once the frame has run and the writer has finished the
  // frames before it.
  RenderedFrame render_frame(uint32_t index, bool capture, CaptureWriter* writer = nullptr);
  const std::vector<PassDecl>& passes() const { return passes_; }
  GpuDevice& gpu() { return gpu_; }
  PassTiming pass_timing() const { return settings_.pass_timing.value_or(default_pass_timing(gpu_.is_cpu())); }

 private:
  GpuDevice& gpu_;
  const Scene& scene_;
  RenderSettings settings_;
  std::vector<PassDecl> passes_;
  ShaderProvider shaders_;
  PipelineCache cache_;
  HistoryPool history_;
  Imports scene_imports_;
  std::set<std::string> features_;  // the scene's, for every frame's skip conditions
  Camera base_;
};

// Built-in SPIR-V of a shader with a pass's `bindings` (binding_defines), compiled once per
// process.
const std::vector<uint32_t>& builtin_spirv(const std::string& path, const std::string& bindings);
// builtin_spirv for every pass: the frame's shaders as built into the binary.
ShaderProvider builtin_shaders();

// Turns an executed frame into the manifest's frame record, writing blobs as it goes.
FrameRecord record_frame(CaptureWriter& writer, const RenderedFrame& frame, uint32_t index);

struct RenderSummary {
  double render_ms = 0, capture_ms = 0;
  uint64_t raw_bytes = 0, disk_bytes = 0;
};

// What the caller sees of a long render, and how it stops one.
struct RenderMonitor {
  std::function<void(const std::string&)> progress = [](const std::string&) {};
  // Polled before every frame and before the capture is committed.
  std::function<bool()> stop_requested = [] { return false; };
};

struct RenderInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// render: every frame into a capture at `out` (atomic), final.png from the last frame. Throws
// RenderInterrupted when the monitor asks to stop; nothing is left at or beside `out` then.
RenderSummary render_to_capture(GpuDevice& gpu, const Scene& scene, const RenderSettings& settings,
                                const std::filesystem::path& out, bool force, const RenderMonitor& monitor = {});
// The same with another assembly of the frame's passes (the supersampled reference), with the
// built-in shaders.
RenderSummary render_to_capture(GpuDevice& gpu, const Scene& scene, const RenderSettings& settings,
                                std::vector<PassDecl> passes, const std::filesystem::path& out, bool force,
                                const RenderMonitor& monitor = {});

}  // namespace nightcap
