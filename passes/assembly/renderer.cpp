#include "passes/assembly/renderer.h"

#include <malloc.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "passes/assembly/frame_passes.h"
#include "passes/core/hash.h"
#include "passes/core/output_pixel.h"
#include "passes/core/shader.h"
#include "passes/frame/camera_math.h"

namespace nightcap {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ResourceRecord describe(const VersionData& v) {
  ResourceRecord r;
  r.resource = v.resource;
  r.kind = v.desc.kind;
  r.is_buffer = v.desc.is_buffer;
  r.format = v.desc.format;
  r.extent = v.desc.extent;
  r.cube = v.desc.cube;
  r.buffer_size = v.desc.buffer_size;
  return r;
}

}  // namespace

NanRequest parse_inject_nan(const std::string& text) {
  const std::string usage = "--inject-nan '" + text + "': expected PASS:X,Y (an output pixel)";
  const size_t colon = text.rfind(':'), comma = text.find(',', colon == std::string::npos ? 0 : colon);
  if (colon == std::string::npos || colon == 0 || comma == std::string::npos) throw SceneError(usage);
  auto coordinate = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
      throw SceneError(usage);
    return uint32_t(std::stoul(digits));
  };
  return {text, text.substr(0, colon), coordinate(text.substr(colon + 1, comma - colon - 1)),
          coordinate(text.substr(comma + 1))};
}

void validate_nan_requests(const std::vector<PassDecl>& passes, const std::vector<NanRequest>& requests, uint32_t width,
                           uint32_t height) {
  std::set<std::string> named;
  for (const NanRequest& request : requests) {
    const std::string flag = "--inject-nan " + request.text + ": ";
    if (!find_pass(passes, request.pass)) throw SceneError(flag + "no pass named '" + request.pass + "'");
    if (!named.insert(request.pass).second) throw SceneError(flag + "a second injection into " + request.pass);
    if (request.x >= width || request.y >= height)
      throw SceneError(flag + "pixel (" + std::to_string(request.x) + ", " + std::to_string(request.y) +
                       ") is outside the " + std::to_string(width) + "x" + std::to_string(height) + " output");
  }
}

namespace {

// The texel of the pass's first float colour output under the requested pixel, from a graph
// compiled for the frame: sizes and formats (a modified resource's included) are known there.
NanInjection resolve_nan_request(const CompiledGraph& graph, const NanRequest& request) {
  const std::string flag = "--inject-nan " + request.text + ": ";
  for (const CompiledPass& pass : graph.passes) {
    if (pass.decl->name != request.pass) continue;
    if (!pass.runs)
      throw SceneError(flag + request.pass + " does not run in frame " +
                       std::to_string(graph.settings.frame.frame_index) + " (" + pass.reason + ")");
    if (pass.decl->type == PassType::cpu)
      throw SceneError(flag + request.pass + " runs on the CPU: the NaN is written on the GPU after a GPU pass");
    for (const BoundUse& out : pass.outputs) {
      if (out.desc.is_buffer || !is_float_colour(*format_info(out.desc.format))) continue;
      return {request.pass, out.resource, texel_under_pixel(request.x, graph.settings.width, out.desc.extent.width),
              texel_under_pixel(request.y, graph.settings.height, out.desc.extent.height)};
    }
    throw SceneError(flag + request.pass + " has no float colour output to hold a NaN");
  }
  throw SceneError(flag + "no pass named '" + request.pass + "'");
}

}  // namespace

void add_default_lighting(Scene& scene) {
  // An empty scene stays empty: a key light would light nothing, and its frame shows what the
  // renderer costs when there is nothing to draw.
  if (!scene.lights.empty() || scene.instances.empty()) return;
  Light key;
  key.type = LightType::directional;
  key.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.6f));
  key.color = glm::vec3(1.0f);
  key.intensity = 3.0f;
  scene.lights.push_back(key);
  scene.notes.push_back("scene has no lights: added a directional key light");
}

Camera base_camera(const Scene& scene, const RenderSettings& settings) {
  if (settings.camera) return *settings.camera;
  if (scene.camera) return *scene.camera;
  return framing_camera(scene, double(settings.width) / settings.height);
}

namespace {

// Each motion's flag name and speed along the view, in metres per second.
struct MotionInfo {
  CameraPath::Motion motion;
  const char* name;
  double speed;
};
constexpr MotionInfo kMotions[] = {{CameraPath::Motion::still, "static", 0.0},
                                   {CameraPath::Motion::walk, "walk", 1.4},
                                   {CameraPath::Motion::drive, "drive", 14.0}};

const MotionInfo& info(CameraPath::Motion motion) {
  for (const MotionInfo& m : kMotions)
    if (m.motion == motion) return m;
  throw std::logic_error("unknown camera motion");
}

}  // namespace

CameraPath::Motion CameraPath::parse_motion(const std::string& name) {
  for (const MotionInfo& m : kMotions)
    if (name == m.name) return m.motion;
  throw SceneError("--motion '" + name + "': expected static, walk or drive");
}

std::string CameraPath::motion_name(Motion motion) { return info(motion).name; }

double CameraPath::speed() const { return speed_override.value_or(info(motion).speed); }

Camera frame_camera(const Camera& base, const Scene& scene, const CameraPath& path, uint32_t frame) {
  const auto cuts_so_far = std::distance(path.cuts.begin(), path.cuts.upper_bound(frame));
  const uint32_t since = cuts_so_far ? *std::prev(path.cuts.upper_bound(frame)) : 0;
  Camera camera = base;
  // The scene's bounds (a pass over every instance) only matter once a cut has turned the view.
  if (cuts_so_far > 0) {
    const glm::dvec3 centre = 0.5 * (glm::dvec3(scene.bounds_min()) + glm::dvec3(scene.bounds_max()));
    const glm::dmat4 turn =
        glm::translate(glm::dmat4(1.0), centre) *
        glm::rotate(glm::dmat4(1.0), glm::half_pi<double>() * double(cuts_so_far), glm::dvec3(0.0, 1.0, 0.0)) *
        glm::translate(glm::dmat4(1.0), -centre);
    camera.world = turn * base.world;
  }
  const glm::dvec3 forward = -glm::dvec3(camera.world[2]);
  camera.world[3] += glm::dvec4(forward * (path.speed() * (frame - since) * kFrameSeconds), 0.0);
  return camera;
}

const std::vector<uint32_t>& builtin_spirv(const std::string& path, const std::string& bindings) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::string>, std::vector<uint32_t>> compiled;
  std::lock_guard lock(mutex);
  auto key = std::make_pair(path, bindings);
  auto it = compiled.find(key);
  if (it == compiled.end()) it = compiled.emplace(key, compile_glsl(path, shader_source(path), bindings)).first;
  return it->second;
}

ShaderProvider builtin_shaders() {
  return [](const std::string&, const std::string& path, const std::string& bindings) {
    return builtin_spirv(path, bindings);
  };
}

namespace {

// Every frame allocates the same large host buffers again (readback staging, each version's
// bytes, encoder scratch). glibc gives large freed blocks back to the system, so each frame
// paid a page fault per 4 KiB of them: 0.3-0.5 s of a capture frame on lavapipe in a VM.
// Keeping freed memory in the heap makes the second and later frames reuse resident pages.
void keep_freed_memory() {
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest allowed value
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  });
}

}  // namespace

Renderer::Renderer(GpuDevice& gpu, const Scene& scene, RenderSettings settings)
    : Renderer(gpu, scene, settings, frame_passes(settings.lighting), builtin_shaders()) {}

Renderer::Renderer(GpuDevice& gpu, const Scene& scene, RenderSettings settings, std::vector<PassDecl> passes,
                   ShaderProvider shaders)
    : gpu_(gpu),
      scene_(scene),
      settings_(std::move(settings)),
      passes_(std::move(passes)),
      shaders_(std::move(shaders)),
      cache_(gpu),
      history_(gpu),
      scene_imports_(scene_imports(scene)),
      features_(scene.features()),
      base_(base_camera(scene, settings_)) {
  validate_nan_requests(passes_, settings_.inject_nan, settings_.width, settings_.height);
  keep_freed_memory();
}

RenderedFrame Renderer::render_frame(uint32_t index, bool capture, CaptureWriter* writer) {
  RenderedFrame frame;
  const bool cut = settings_.path.cut_at(index);
  frame.camera = frame_camera(base_, scene_, settings_.path, index);
  frame.time = index * kFrameSeconds;
  // Across a cut nothing moved on screen: the previous view is another shot.
  const Camera previous = index == 0 || cut ? frame.camera : frame_camera(base_, scene_, settings_.path, index - 1);
  Imports imports = scene_imports_;
  for (auto& [name, data] : camera_import(frame.camera, previous, settings_.width, settings_.height, index, cut))
    imports[name] = data;

  GraphSettings graph_settings;
  graph_settings.width = settings_.width;
  graph_settings.height = settings_.height;
  graph_settings.frame.features = features_;
  graph_settings.frame.frame_index = index;
  graph_settings.frame.camera_moved = previous.world != frame.camera.world;
  graph_settings.frame.camera_cut = cut;
  graph_settings.sinks = settings_.sinks.empty() ? frame_sinks() : settings_.sinks;
  graph_settings.params = settings_.params;
  graph_settings.capture = capture;
  graph_settings.readback = settings_.readback;
  graph_settings.readback.insert("final.ldr");
  for (const PassDecl& pass : passes_)
    for (const PassDecl::OutputWarning& warning : pass.warnings) graph_settings.readback.insert(warning.output);
  frame.graph = compile_graph(passes_, as_graph_imports(imports), graph_settings);
  if (!settings_.inject_nan.empty()) {
    for (const NanRequest& request : settings_.inject_nan)
      graph_settings.nan_injections.push_back(resolve_nan_request(frame.graph, request));
    frame.graph = compile_graph(passes_, as_graph_imports(imports), graph_settings);
  }

  ExecutionOptions options;
  options.shaders = shaders_;
  options.history = &history_;
  options.alias_memory = settings_.alias_memory;
  options.pass_timing = pass_timing();
  // No encoding of earlier frames may run beside a pass timed alone.
  if (capture && writer && options.pass_timing == PassTiming::alone) writer->flush();
  if (capture && writer)
    options.on_read_back = [writer](const VersionData& version) {
      ResourceRecord record = describe(version);
      writer->add_resource(record, version.bytes);
    };
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> bytes;
  for (const auto& [name, data] : imports) bytes[name] = data.bytes;
  frame.execution = execute_graph(gpu_, cache_, frame.graph, bytes, options);
  for (const CompiledPass& pass : frame.graph.passes) {
    if (!pass.runs) continue;
    for (const PassDecl::OutputWarning& warning : pass.decl->warnings) {
      const VersionData* version = frame.execution.final_version(warning.output);
      if (!version || !version->bytes) continue;
      const std::string message = warning.check(*version->bytes);
      if (message.empty()) continue;
      frame.warnings.push_back(pass.decl->name + ": " + message);
      std::cerr << "warning: frame " << index << ": " << frame.warnings.back() << "\n";
    }
  }
  return frame;
}

FrameRecord record_frame(CaptureWriter& writer, const RenderedFrame& frame, uint32_t index) {
  FrameRecord record;
  record.index = index;
  record.width = frame.graph.settings.width;
  record.height = frame.graph.settings.height;
  record.sinks = frame.graph.settings.sinks;
  record.time = frame.time;
  record.wall_ms = frame.execution.wall_ms;
  record.camera_cut = frame.graph.settings.frame.camera_cut;
  record.history_reset = frame.execution.history_reset;
  const CameraRecordGpu* camera = nullptr;
  if (const VersionData* v = frame.execution.final_version("frame.camera"))
    camera = reinterpret_cast<const CameraRecordGpu*>(v->bytes->data());
  const glm::dmat4 view = relative_view(frame.camera.world);
  const glm::dmat4 projection = reversed_z_projection(
      frame.camera.yfov, camera ? double(camera->width) / camera->height : 1.0, frame.camera.znear);
  for (int k = 0; k < 16; ++k) {
    record.camera.view[k] = (&view[0][0])[k];
    record.camera.projection[k] = (&projection[0][0])[k];
  }
  for (int k = 0; k < 3; ++k) record.camera.position[k] = frame.camera.world[3][k];
  record.camera.yfov = frame.camera.yfov;
  record.camera.znear = frame.camera.znear;

  record.passes.reserve(frame.graph.passes.size());
  for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
    const CompiledPass& pass = frame.graph.passes[i];
    const PassExecution& exec = frame.execution.passes[i];
    PassRecord p;
    p.name = pass.decl->name;
    p.stage = pass.decl->stage;
    p.ran = pass.runs && !pass.culled;
    p.reason = pass.reason;
    p.gpu_ms = exec.gpu_ms;
    p.cpu_ms = exec.cpu_ms;
    p.time_ms = exec.time_ms;
    p.clock = exec.clock;
    p.record_ms = exec.record_ms;
    p.params = pass.params;
    p.param_types = pass.decl->params;
    for (const auto& [path, code] : exec.spirv) p.shaders.push_back(writer.add_shader(path, code, shader_source(path)));
    p.pipelines = exec.pipelines;
    p.samplers = exec.samplers;
    for (const NanInjection& nan : pass.sync.injections) p.injected_nan = InjectedNanRecord{nan.resource, nan.x, nan.y};
    for (int v : exec.inputs) p.inputs.push_back(describe(frame.execution.versions[v]));
    for (int v : exec.outputs) {
      p.outputs.push_back(describe(frame.execution.versions[v]));
      p.outputs.back().contract = pass.decl->contract_of(p.outputs.back().resource);
      if (const BufferSchema* schema = pass.decl->schema_of(p.outputs.back().resource))
        p.outputs.back().schema = *schema;
    }
    record.passes.push_back(std::move(p));
  }
  // A version read by several passes is hashed and queued once; the writer encodes it in the
  // background.
  std::map<int, const ResourceRecord*> added;
  auto add = [&](ResourceRecord& resource, int version) {
    if (auto it = added.find(version); it != added.end()) {
      resource.hash = it->second->hash;
      resource.blob = it->second->blob;
      return;
    }
    const VersionData& data = frame.execution.versions[version];
    if (!data.bytes) throw GraphError("resource '" + resource.resource + "' was not read back for the capture");
    writer.add_resource(resource, data.bytes);
    added[version] = &resource;
  };
  for (size_t i = 0; i < record.passes.size(); ++i) {
    const PassExecution& exec = frame.execution.passes[i];
    for (size_t k = 0; k < exec.inputs.size(); ++k) add(record.passes[i].inputs[k], exec.inputs[k]);
    for (size_t k = 0; k < exec.outputs.size(); ++k) add(record.passes[i].outputs[k], exec.outputs[k]);
  }
  return record;
}

RenderSummary render_to_capture(GpuDevice& gpu, const Scene& scene, const RenderSettings& settings,
                                const std::filesystem::path& out, bool force, const RenderMonitor& monitor) {
  return render_to_capture(gpu, scene, settings, frame_passes(settings.lighting), out, force, monitor);
}

RenderSummary render_to_capture(GpuDevice& gpu, const Scene& scene, const RenderSettings& settings,
                                std::vector<PassDecl> passes, const std::filesystem::path& out, bool force,
                                const RenderMonitor& monitor) {
  RenderSummary summary;
  const uint32_t first = settings.first_recorded, last = std::min(settings.last_recorded, settings.frames - 1);
  if (first > last)
    throw SceneError("--record-frames: frame " + std::to_string(first) + " is past the last frame, " +
                     std::to_string(settings.frames - 1));
  CaptureWriter writer(out, force, settings.capture);
  Renderer renderer(gpu, scene, settings, std::move(passes), builtin_shaders());
  CaptureManifest manifest;
  manifest.device = {{"name", gpu.name()},
                     {"driver", gpu.driver()},
                     {"api_version", std::to_string(VK_API_VERSION_MAJOR(gpu.properties().apiVersion)) + "." +
                                         std::to_string(VK_API_VERSION_MINOR(gpu.properties().apiVersion)) + "." +
                                         std::to_string(VK_API_VERSION_PATCH(gpu.properties().apiVersion))},
                     {"vendor_id", gpu.properties().vendorID},
                     {"device_id", gpu.properties().deviceID}};
  // As given on the command line, and as resolved: what every frame of the capture shares.
  manifest.settings = settings.description;
  manifest.settings["resolved"] = {{"width", settings.width},
                                   {"height", settings.height},
                                   {"frames", settings.frames},
                                   {"recorded_frames", {first, last}},
                                   {"frame_seconds", kFrameSeconds},
                                   {"motion", CameraPath::motion_name(settings.path.motion)},
                                   {"speed_m_per_s", settings.path.speed()},
                                   {"cuts", settings.path.cuts},
                                   {"sinks", frame_sinks()},
                                   {"pass_times", pass_timing_name(renderer.pass_timing())}};
  manifest.scene = {{"source", scene.source},
                    {"instances", scene.instances.size()},
                    {"triangles", scene.indices.size() / 3},
                    {"materials", scene.materials.size()},
                    {"textures", scene.textures.size()},
                    {"lights", scene.lights.size()},
                    {"notes", scene.notes}};
  gpu.renderdoc_begin();
  std::vector<uint8_t> final_pixels;
  try {
    // Every frame up to the last recorded one renders, so history carries into the recorded ones.
    for (uint32_t k = 0; k <= last; ++k) {
      if (monitor.stop_requested()) throw RenderInterrupted("interrupted: no capture written to " + out.string());
      monitor.progress("frame " + std::to_string(k + 1) + "/" + std::to_string(last + 1) + ": rendering");
      auto start = std::chrono::steady_clock::now();
      const bool recorded = k >= first;
      RenderedFrame frame = renderer.render_frame(k, recorded, &writer);
      summary.render_ms += ms_since(start);
      if (!recorded) continue;
      monitor.progress("frame " + std::to_string(k + 1) + "/" + std::to_string(last + 1) + ": writing capture");
      start = std::chrono::steady_clock::now();
      manifest.frames.push_back(record_frame(writer, frame, k));
      summary.capture_ms += ms_since(start);
      for (const VersionData& v : frame.execution.versions) summary.raw_bytes += v.bytes ? v.bytes->size() : 0;
      if (const VersionData* final = frame.execution.final_version("final.ldr")) final_pixels = *final->bytes;
    }
  } catch (...) {
    gpu.renderdoc_end();
    throw;
  }
  gpu.renderdoc_end();
  if (!final_pixels.empty()) writer.write_final_png(final_pixels, settings.width, settings.height);
  if (monitor.stop_requested()) throw RenderInterrupted("interrupted: no capture written to " + out.string());
  writer.commit(manifest);
  summary.disk_bytes = writer.bytes_written();
  return summary;
}

}  // namespace nightcap
