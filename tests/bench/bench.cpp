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
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <thread>

#include "captures/blob_codec.h"
#include "captures/capture.h"
#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/core/isolated.h"
#include "passes/cull/cull_stats.h"
#include "passes/cull/stage.h"
#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/frame/gpu_types.h"
#include "passes/gbuffer/kinds.h"
#include "passes/lighting/ltc/fit.h"
#include "passes/lighting/stage.h"
#include "passes/lights/cluster_layout.h"
#include "passes/lights/stage.h"
#include "passes/motion/stage.h"
#include "passes/normals/bfn_lut.h"
#include "passes/normals/stage.h"
#include "passes/post/exposure.glsl.h"
#include "passes/post/stage.h"
#include "passes/scene/scene.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/shadow_layout.h"
#include "tests/reference/bloom_reference.h"
#include "tests/reference/decal_reference.h"
#include "tests/reference/depth_half_reference.h"
#include "tests/reference/lighting_reference.h"
#include "tests/reference/local_shadow_reference.h"
#include "tests/reference/ltc_reference.h"
#include "tests/reference/motion_mask_reference.h"
#include "tests/reference/shadow_reference.h"
#include "tests/unit/recorded_pass.h"

namespace nc = nightcap;
namespace fs = std::filesystem;
namespace ref = nightcap::reference;

namespace {

// Tables for a person go to stdout; with --json they go to stderr and stdout carries only
// {"figures": {NAME: NUMBER}}, every number of the tables under a stable name.
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

void bench_capture_cost(nc::Renderer& renderer, const nc::RenderSettings& settings, int repeats);

// Per-pass medians over `repeats` frames, capture off, and the frame's GPU memory; with
// `capture_figures`, frame time off/on and capture size too, and the unsuffixed figures.
void bench_scene(nc::GpuDevice& gpu, const std::string& key, const std::string& label, nc::Scene scene, uint32_t width,
                 uint32_t height, int repeats, bool capture_figures) {
  nc::add_default_lighting(scene);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  nc::Renderer renderer(gpu, scene, settings);
  renderer.render_frame(0, false);  // pipelines compiled outside the measurement
  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<std::string> order;
  std::vector<double> frame_off, frame_on;
  uint64_t memory = 0, memory_without_aliasing = 0;
  for (int r = 0; r < repeats; ++r) {
    double start = now_ms();
    nc::RenderedFrame frame = renderer.render_frame(0, false);
    frame_off.push_back(now_ms() - start);
    memory = frame.execution.memory_bytes;
    memory_without_aliasing = frame.execution.memory_bytes_without_aliasing;
    for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
      const std::string& name = frame.graph.passes[i].decl->name;
      if (r == 0) order.push_back(name);
      const auto& exec = frame.execution.passes[i];
      if (!frame.graph.passes[i].runs) continue;
      pass_ms[name].push_back(exec.gpu_ms ? *exec.gpu_ms : exec.cpu_ms);
    }
  }
  table() << "\n## " << label << " (" << width << "x" << height << ", " << scene.indices.size() / 3 << " triangles, "
          << scene.lights.size() << " lights; median of " << repeats << ")\n";
  table() << std::left << std::setw(22) << "pass" << std::right << std::setw(12) << "ms"
          << "\n";
  for (const std::string& name : order) {
    table() << std::left << std::setw(22) << name << std::right << std::setw(12);
    if (pass_ms[name].empty())
      table() << "skipped";
    else
      table() << std::fixed << std::setprecision(3) << median(pass_ms[name]);
    table() << "\n";
    if (!pass_ms[name].empty()) figure("pass_ms." + key + "." + name, median(pass_ms[name]));
  }
  figure("frame_ms." + key, median(frame_off));
  table() << std::left << std::setw(22) << "frame (capture off)" << std::right << std::setw(12) << median(frame_off)
          << "\n";
  // Device memory of the frame's resources: transients sharing memory where their lifetimes
  // allow, and each in its own.
  const double mib = memory / 1048576.0, mib_apart = memory_without_aliasing / 1048576.0;
  table() << std::left << std::setw(22) << "GPU memory (MiB)" << std::right << std::setw(12) << std::setprecision(1)
          << mib << "  (" << mib_apart << " without aliasing)\n";
  figure("peak_gpu_mib." + key, mib);
  figure("peak_gpu_mib_no_aliasing." + key, mib_apart);
  if (!capture_figures) return;
  figure("peak_gpu_mib", mib);
  figure("peak_gpu_mib_no_aliasing", mib_apart);
  bench_capture_cost(renderer, settings, repeats);
}

// Capture on against off on the warm renderer, frames alternating so that both see the same
// machine: readback, hashing, encoding every blob and committing the capture folder (manifest,
// fsync), against the frame alone. Then the encoding alone, codec by codec and with 1 or all
// cores, on one frame's resources.
void bench_capture_cost(nc::Renderer& renderer, const nc::RenderSettings& settings, int repeats) {
  const fs::path dir = fs::temp_directory_path() / "nightcap-bench";
  fs::remove_all(dir);
  std::vector<double> frame_off, frame_on;
  uint64_t raw = 0, disk = 0;
  for (int r = 0; r < repeats; ++r) {
    double start = now_ms();
    renderer.render_frame(0, false);
    frame_off.push_back(now_ms() - start);
    start = now_ms();
    nc::CaptureWriter writer(dir / ("on" + std::to_string(r)), false, settings.capture);
    nc::CaptureManifest manifest;
    const nc::RenderedFrame frame = renderer.render_frame(0, true, &writer);
    manifest.frames.push_back(nc::record_frame(writer, frame, 0));
    writer.commit(manifest);
    frame_on.push_back(now_ms() - start);
    raw = 0;
    for (const nc::VersionData& v : frame.execution.versions) raw += v.bytes ? v.bytes->size() : 0;
    disk = writer.bytes_written();
  }
  table() << std::left << std::setw(22) << "frame (capture on)" << std::right << std::setw(12) << std::fixed
          << std::setprecision(3) << median(frame_on) << "  (" << std::setprecision(2)
          << median(frame_on) / median(frame_off) << "x capture off, " << median(frame_off) << " ms; "
          << std::setprecision(1) << disk / 1048576.0 << " MiB on disk, " << std::setprecision(3) << double(disk) / raw
          << " of " << std::setprecision(1) << raw / 1048576.0 << " MiB raw)\n";
  figure("capture_frame_ms", median(frame_on));
  figure("capture_on_off_ratio", median(frame_on) / median(frame_off));
  figure("capture_bytes_ratio", double(disk) / raw);

  const nc::RenderedFrame frame = renderer.render_frame(0, true);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  struct Row {
    std::string codec;
    unsigned workers;
    double ms;
    uint64_t bytes;
  };
  std::vector<Row> rows;
  for (const char* codec : {"auto", "zip1", "zip4", "zips1", "piz", "pxr24_1", "rle", "none"})
    for (unsigned workers : {1u, cores})
      if (workers == 1 || cores > 1) rows.push_back({codec, workers, 0, 0});
  // Round after round over every row, so that a busy spell of the machine spreads over all.
  std::vector<std::vector<double>> times(rows.size());
  for (int r = 0; r < repeats; ++r)
    for (size_t i = 0; i < rows.size(); ++i) {
      nc::CaptureWriter::Options options;
      if (rows[i].codec != "auto") options.images = nc::image_encoding_by_name(rows[i].codec);
      options.workers = rows[i].workers;
      fs::remove_all(dir / "encode");
      nc::CaptureWriter writer(dir / "encode", false, options);
      const double start = now_ms();
      nc::record_frame(writer, frame, 0);
      writer.flush();
      times[i].push_back(now_ms() - start);
      rows[i].bytes = writer.bytes_written();
    }
  for (size_t i = 0; i < rows.size(); ++i) rows[i].ms = median(times[i]);
  table() << "\nencoding one frame's resources (" << std::fixed << std::setprecision(1) << raw / 1048576.0
          << " MiB raw; Pareto: no other codec with as many workers is both faster and smaller)\n"
          << "  codec      workers        ms   MB/s/core   of raw   Pareto\n";
  for (const Row& row : rows) {
    const bool pareto = std::none_of(rows.begin(), rows.end(), [&](const Row& other) {
      return other.workers == row.workers && other.ms <= row.ms && other.bytes <= row.bytes &&
             (other.ms < row.ms || other.bytes < row.bytes);
    });
    const double mb_per_s_core = raw / 1e6 / (row.ms / 1000.0) / row.workers;
    table() << "  " << std::left << std::setw(10) << row.codec << std::right << std::setw(8) << row.workers
            << std::setprecision(1) << std::setw(10) << row.ms << std::setw(12) << mb_per_s_core << std::setprecision(3)
            << std::setw(9) << double(row.bytes) / raw << std::setw(9) << (pareto ? "yes" : "") << "\n";
    const std::string key = row.codec + ".workers" + std::to_string(row.workers);
    figure("capture_encode_ms." + key, row.ms);
    figure("capture_encode_bytes_ratio." + key, double(row.bytes) / raw);
    figure("capture_encode_pareto." + key, pareto ? 1 : 0);
    if (row.codec == "auto" && row.workers == 1) figure("capture_mb_per_s", mb_per_s_core);
  }
  fs::remove_all(dir);
}

// What each frame after the first adds to a capture of the city: a resource equal to one already
// stored is stored once, so a still camera should add little and a walking one nearly a frame.
void bench_extra_frames(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  constexpr uint32_t kFrames = 4;
  nc::Scene scene = nc::build_city(1);
  nc::add_default_lighting(scene);
  const fs::path dir = fs::temp_directory_path() / "nightcap-bench-frames";
  table() << "\n## capture size per extra frame (city, " << width << "x" << height << ", 1 and " << kFrames
          << " frames)\n";
  const std::pair<const char*, nc::CameraPath::Motion> motions[] = {{"static", nc::CameraPath::Motion::still},
                                                                    {"moving", nc::CameraPath::Motion::walk}};
  for (const auto& [name, motion] : motions) {
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = motion;
    uint64_t disk[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
      settings.frames = i == 0 ? 1 : kFrames;
      fs::remove_all(dir);
      disk[i] = nc::render_to_capture(gpu, scene, settings, dir, false).disk_bytes;
    }
    const double per_frame = (double(disk[1]) - double(disk[0])) / (kFrames - 1) / 1048576.0;
    table() << "  " << std::left << std::setw(8) << name << std::right << std::fixed << std::setprecision(2)
            << std::setw(8) << per_frame << " MiB per extra frame (one frame: " << disk[0] / 1048576.0 << " MiB)\n";
    figure(std::string("capture_mib_per_extra_frame_") + name, per_frame);
  }
  fs::remove_all(dir);
}

// Runs ARGV (its first word the program, looked up in PATH unless it holds a '/') with standard
// output into `out`, and standard error discarded when `quiet`; waits for it. Its exit status, or
// -1 when it could not start or was killed.
int run_program(std::vector<std::string> argv, const char* out, bool quiet) {
  std::vector<char*> words;
  for (std::string& a : argv) words.push_back(a.data());
  words.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (quiet) posix_spawn_file_actions_addopen(&files, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, words.front(), &files, nullptr, words.data(), environ);
  int status = 0;
  if (error == 0) waitpid(pid, &status, 0);
  posix_spawn_file_actions_destroy(&files);
  return error == 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Wall-clock milliseconds of one run of ARGV, output discarded; a run whose exit status
// `accepted` refuses throws.
double timed_run_ms(const std::vector<std::string>& argv, const std::function<bool(int)>& accepted) {
  const double start = now_ms();
  const int code = run_program(argv, "/dev/null", true);
  const double elapsed = now_ms() - start;
  if (!accepted(code)) throw std::runtime_error(argv.front() + " " + argv.at(1) + " exited " + std::to_string(code));
  return elapsed;
}

// Median wall-clock milliseconds of ARGV over 5 runs after one that warms the file cache.
double warm_median_ms(const std::vector<std::string>& argv, const std::function<bool(int)>& accepted) {
  std::vector<double> runs;
  for (int r = 0; r < 6; ++r) {
    const double elapsed = timed_run_ms(argv, accepted);
    if (r > 0) runs.push_back(elapsed);
  }
  return median(runs);
}

// Medians of two programs run in turn (x, y, x, y, ...; the first round warms up): a difference
// of the two is then taken over the same stretch of a noisy machine. Each run's exit code must be
// accepted.
std::pair<double, double> alternating_medians_ms(const std::vector<std::string>& x, const std::vector<std::string>& y,
                                                 const std::function<bool(int)>& accepted_x,
                                                 const std::function<bool(int)>& accepted_y, int runs) {
  std::vector<double> x_ms, y_ms;
  for (int r = 0; r <= runs; ++r) {
    const double x_run = timed_run_ms(x, accepted_x), y_run = timed_run_ms(y, accepted_y);
    if (r == 0) continue;
    x_ms.push_back(x_run);
    y_ms.push_back(y_run);
  }
  return {median(x_ms), median(y_ms)};
}

// The same for `nightcap ARGS`, which must exit with `exit_code`.
double cli_median_ms(const std::vector<std::string>& args, int exit_code = 0) {
  std::vector<std::string> argv = {NIGHTCAP_CLI};
  argv.insert(argv.end(), args.begin(), args.end());
  return warm_median_ms(argv, [exit_code](int code) { return code == exit_code; });
}

// A one-frame capture of the built-in city (seed 1, default lighting) in `dir`, with `params`.
void render_city(nc::GpuDevice& gpu, uint32_t width, uint32_t height, const fs::path& dir,
                 const std::map<std::string, nc::ParamValues>& params = {}) {
  nc::Scene scene = nc::build_city(1);
  nc::add_default_lighting(scene);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.params = params;
  nc::render_to_capture(gpu, scene, settings, dir, false);
}

// Peak resident MiB of `nightcap ARGS`, measured by peak_rss (tests/bench/peak_rss.cpp says why
// not here); a failed run throws.
double cli_peak_mib(const std::vector<std::string>& args) {
  const fs::path result = fs::temp_directory_path() / ("nightcap-bench-peak-" + std::to_string(getpid()));
  std::vector<std::string> argv = {NIGHTCAP_PEAK_RSS, NIGHTCAP_CLI};
  argv.insert(argv.end(), args.begin(), args.end());
  const bool ok = run_program(argv, result.c_str(), false) == 0;
  std::ifstream in(result);
  long kib = -1;
  in >> kib;
  fs::remove(result);
  if (!ok || kib < 0)
    throw std::runtime_error(std::string(NIGHTCAP_CLI) + " " + args.front() + " failed under peak_rss");
  return kib / 1024.0;
}

// How long the CLI takes before it has done anything: `--help`, and `passes` of a one-frame city
// capture, which reads the manifest and nothing else; and the debugger's first answer, one
// decoded pixel of gbuffer.normal (one blob read), with the peak memory of that process. Median of
// 5 runs after one that warms the file cache.
void bench_startup(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  const fs::path dir = fs::temp_directory_path() / "nightcap-bench-startup";
  fs::remove_all(dir);
  render_city(gpu, width, height, dir);
  const double help = cli_median_ms({"--help"}), passes = cli_median_ms({"passes", dir.string()});
  const std::vector<std::string> first_answer = {
      "inspect", dir.string(), "-c",
      "pixel " + std::to_string(width / 2) + " " + std::to_string(height / 2) + " gbuffer.normal"};
  const double inspect = cli_median_ms(first_answer);
  const double peak_mib = cli_peak_mib(first_answer);
  // RenderDoc 1.24's "save the five G-buffer targets" as uncompressed half EXR, the same way.
  const fs::path exported = dir / "exported";
  fs::create_directories(exported);
  std::string export_commands = "goto gbuffer.opaque";
  for (const char* target : {"albedo", "normal", "material", "motion", "emissive"})
    export_commands += std::string("; export gbuffer.") + target + " --half --uncompressed -o " +
                       (exported / (std::string(target) + ".exr")).string();
  const double export_pass = cli_median_ms({"inspect", dir.string(), "-c", export_commands});
  table() << "\n## CLI start-up, wall clock (median of 5 runs, warm file cache)\n"
          << std::fixed << std::setprecision(1) << "  nightcap --help          " << std::setw(7) << help << " ms\n"
          << "  nightcap passes CAP      " << std::setw(7) << passes << " ms (city, " << width << "x" << height
          << ", 1 frame)\n"
          << "  nightcap inspect CAP -c 'pixel " << width / 2 << " " << height / 2 << " gbuffer.normal' "
          << std::setw(7) << inspect << " ms, peak " << peak_mib << " MiB\n"
          << "  nightcap inspect CAP -c 'export' of gbuffer.opaque's five colour targets as uncompressed half EXR "
          << std::setw(7) << export_pass << " ms\n";
  figure("startup_ms_help", help);
  figure("inspect_first_answer_ms", inspect);
  figure("inspect_peak_mib", peak_mib);
  figure("inspect_export_pass_ms", export_pass);
  figure("startup_ms_passes", passes);
  fs::remove_all(dir);
}

// Reading one 1280x720 RGBA16F blob of a capture (lighting.tiled's diffuse light, ZIP), median
// of 9 after a warm-up: nightcap's reader (OpenEXR's core library, libdeflate, a part's chunks
// split among threads) against OpenEXR's C++ library reading the same file on one thread and on
// as many as nightcap uses.
//  - blob_read_ms, blob_read_openexr_ms, blob_read_openexr_threads_ms.
void bench_blob_read(const nc::Capture& capture, const nc::FrameRecord& frame) {
  const nc::ResourceRecord* record = nullptr;
  for (const nc::PassRecord& p : frame.passes)
    for (const nc::ResourceRecord& r : p.outputs)
      if (!record && r.resource == "lighting.diffuse") record = &r;
  if (!record || record->format != VK_FORMAT_R16G16B16A16_SFLOAT)
    throw std::runtime_error("the city capture has no RGBA16F lighting.diffuse");
  const fs::path file = capture.blob_file(record->blob);
  auto timed = [](const std::function<void()>& read) {
    read();
    std::vector<double> ms;
    for (int i = 0; i < 9; ++i) {
      const auto start = std::chrono::steady_clock::now();
      read();
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    return median(ms);
  };
  const nc::FormatInfo format = *nc::format_info(record->format);
  const double nightcap = timed([&] { nc::read_image_blob(file, format, record->extent); });
  std::vector<uint16_t> texels(size_t(record->extent.width) * record->extent.height * 4);
  auto openexr = [&](int threads) {
    Imf::MultiPartInputFile in(file.c_str(), threads);
    Imf::InputPart part(in, 0);
    const Imath::Box2i window = in.header(0).dataWindow();
    Imf::FrameBuffer frame_buffer;
    const char* names[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
      frame_buffer.insert(names[c],
                          Imf::Slice::Make(Imf::HALF, texels.data() + c, window, 8, 8 * size_t(record->extent.width)));
    part.setFrameBuffer(frame_buffer);
    part.readPixels(window.min.y, window.max.y);
  };
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const double openexr_one = timed([&] { openexr(0); });
  const double openexr_threads = timed([&] { openexr(threads); });
  table() << std::fixed << std::setprecision(1) << "  reading one 1280x720 RGBA16F ZIP blob: nightcap " << nightcap
          << " ms, OpenEXR's C++ library " << openexr_one << " ms on one thread, " << openexr_threads << " ms on "
          << threads << "\n";
  figure("blob_read_ms", nightcap);
  figure("blob_read_openexr_ms", openexr_one);
  figure("blob_read_openexr_threads_ms", openexr_threads);
}

// `nightcap diff` of two city captures that differ in lighting.tiled's intensity, so every
// output from lighting down differs, against OpenImageIO's idiff over the same image pairs (the
// blobs are EXR files idiff reads). Medians of 7 runs after one that warms the file cache.
//  - diff_capture_ms: the whole CLI run, FLIP of the displayed image included;
//  - diff_vs_idiff_ratio: time per differing image, idiff's over nightcap's, each less its
//    start-up (idiff's on a 1x1 pair, nightcap's on a diff of a capture with itself, which
//    reads both manifests and compares hashes). Each is timed in turn with its start-up, idiff's
//    pair by pair: idiff's start-up is most of each of its runs, and measured apart from them it
//    moved the ratio between 3.9 and 6.5 from one run of the benchmark to the next.
void bench_diff(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  const fs::path dir = fs::temp_directory_path() / ("nightcap-bench-diff-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const fs::path a = dir / "a", b = dir / "b";
  render_city(gpu, width, height, a);
  render_city(gpu, width, height, b, {{"lighting.tiled", {{"intensity_scale", 1.5}}}});
  const auto [diff, diff_itself] = alternating_medians_ms(
      {NIGHTCAP_CLI, "diff", a.string(), b.string()}, {NIGHTCAP_CLI, "diff", a.string(), a.string()},
      [](int code) { return code == 1; }, [](int code) { return code == 0; }, 7);

  // The image outputs whose bytes differ, as pairs of blob files.
  const nc::Capture ca = nc::Capture::open(a), cb = nc::Capture::open(b);
  std::vector<std::pair<fs::path, fs::path>> pairs;
  const nc::FrameRecord &fa = ca.frame(0), &fb = cb.frame(0);
  for (size_t p = 0; p < fa.passes.size() && p < fb.passes.size(); ++p)
    for (const nc::ResourceRecord& ra : fa.passes[p].outputs)
      for (const nc::ResourceRecord& rb : fb.passes[p].outputs)
        if (ra.resource == rb.resource && !ra.is_buffer && ra.hash != rb.hash)
          pairs.emplace_back(a / ra.blob, b / rb.blob);
  // idiff exits 0 (match), 1 (within its warning threshold) or 2 (differs): any of them is a
  // comparison made.
  const fs::path tiny = dir / "tiny.exr";
  if (run_program(
          {"oiiotool", "--pattern", "constant:color=0.5,0.5,0.5", "1x1", "3", "-d", "half", "-o", tiny.string()},
          "/dev/null", true) != 0)
    throw std::runtime_error("oiiotool could not write " + tiny.string());
  const auto compared = [](int code) { return code >= 0 && code <= 2; };
  double idiff_total = 0.0, idiff_starts = 0.0;
  for (const auto& [x, y] : pairs) {
    const auto [pair_ms, start_ms] = alternating_medians_ms(
        {"idiff", x.string(), y.string()}, {"idiff", tiny.string(), tiny.string()}, compared, compared, 5);
    idiff_total += pair_ms;
    idiff_starts += start_ms;
  }
  const double n = double(pairs.size());
  const double idiff_start = idiff_starts / n;
  const double idiff_per_image = (idiff_total - idiff_starts) / n;
  const double nightcap_per_image = (diff - diff_itself) / n;
  table() << "\n## diff of two city captures (" << width << "x" << height
          << ", lighting.tiled.intensity_scale 1 vs 1.5; medians of 7 runs, idiff's of 5)\n"
          << std::fixed << std::setprecision(1) << "  nightcap diff A B        " << std::setw(8) << diff
          << " ms (A A: " << diff_itself << " ms), " << pairs.size() << " differing images\n"
          << "  idiff, the same pairs   " << std::setw(8) << idiff_total << " ms (1x1 pair: " << idiff_start
          << " ms, the mean of its medians)\n"
          << "  per differing image, start-up removed: idiff " << idiff_per_image << " ms, nightcap "
          << nightcap_per_image << " ms, ratio " << std::setprecision(2) << idiff_per_image / nightcap_per_image
          << "\n";
  figure("diff_capture_ms", diff);
  figure("diff_itself_ms", diff_itself);
  figure("diff_idiff_pairs_ms", idiff_total);
  figure("diff_vs_idiff_ratio", idiff_per_image / nightcap_per_image);
  bench_blob_read(ca, fa);
  fs::remove_all(dir);
}

uint64_t folder_bytes(const fs::path& folder) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

// `nightcap report` of a city capture, and of the diff of two that differ in
// lighting.tiled's intensity (as bench_diff), each the whole CLI run (median of 5 after one
// that warms the file cache; --force replaces the report each time).
//  - report_ms, report_diff_ms: the runs;
//  - report_bytes_ratio: the capture report folder's bytes over the capture folder's;
//  - report_diff_bytes_ratio: the diff report folder's bytes over the two captures'.
void bench_report(nc::GpuDevice& gpu, uint32_t width, uint32_t height) {
  const fs::path dir = fs::temp_directory_path() / ("nightcap-bench-report-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const fs::path a = dir / "a", b = dir / "b", report = dir / "report", diff_report = dir / "diff-report";
  render_city(gpu, width, height, a);
  render_city(gpu, width, height, b, {{"lighting.tiled", {{"intensity_scale", 1.5}}}});
  const double ms = cli_median_ms({"report", a.string(), "-o", report.string(), "--force"});
  const double diff_ms = cli_median_ms({"report", a.string(), b.string(), "-o", diff_report.string(), "--force"});
  const double ratio = double(folder_bytes(report)) / double(folder_bytes(a));
  const double diff_ratio = double(folder_bytes(diff_report)) / double(folder_bytes(a) + folder_bytes(b));
  table() << "\n## reports of city captures (" << width << "x" << height << "; median of 5 runs)\n"
          << std::fixed << std::setprecision(1) << "  nightcap report CAP        " << std::setw(8) << ms << " ms, "
          << folder_bytes(report) / 1024 << " KiB for a capture of " << folder_bytes(a) / 1024 << " KiB (ratio "
          << std::setprecision(3) << ratio << ")\n"
          << std::setprecision(1) << "  nightcap report CAP_A CAP_B" << std::setw(8) << diff_ms << " ms, "
          << folder_bytes(diff_report) / 1024 << " KiB for captures of " << (folder_bytes(a) + folder_bytes(b)) / 1024
          << " KiB (ratio " << std::setprecision(3) << diff_ratio << ")\n";
  figure("report_ms", ms);
  figure("report_bytes_ratio", ratio);
  figure("report_diff_ms", diff_ms);
  figure("report_diff_bytes_ratio", diff_ratio);
  fs::remove_all(dir);
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

// frame.constants as an input of a pass run on its own.
nc::IsolatedInput constants_input(const nc::GpuFrameConstants& constants) {
  nc::IsolatedInput input;
  input.desc.is_buffer = true;
  input.desc.kind = nc::kinds::buffer;
  input.desc.buffer_size = sizeof(constants);
  auto bytes = std::make_shared<std::vector<uint8_t>>(sizeof(constants));
  std::memcpy(bytes->data(), &constants, sizeof(constants));
  input.bytes = bytes;
  return input;
}

double gpu_ms(const nc::IsolatedRun& run) { return run.execution.passes.at(0).gpu_ms.value_or(0.0); }

// A pass's time in a frame: by timestamps on the GPU, on the clock for a CPU pass; 0 when it did
// not run.
double frame_pass_ms(const nc::RenderedFrame& frame, const std::string& pass) {
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass && frame.graph.passes[i].runs) {
      const nc::PassExecution& exec = frame.execution.passes[i];
      return exec.gpu_ms ? *exec.gpu_ms : exec.cpu_ms;
    }
  return 0.0;
}

// normals.pack: LUT size against mean/max angular error over a Fibonacci sphere.
void bench_normals(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t count) {
  const uint32_t width = 2048, height = (count + width - 1) / width;
  std::vector<uint8_t> normals(size_t(width) * height * 4), material(size_t(width) * height * 4, 128);
  std::vector<glm::dvec3> inputs(size_t(width) * height);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (size_t i = 0; i < inputs.size(); ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / inputs.size(), r = std::sqrt(1.0 - y * y);
    const glm::dvec3 d(std::cos(golden * i) * r, y, std::sin(golden * i) * r);
    auto code = [](double v) { return uint32_t(std::lround((v * 0.5 + 0.5) * 1023.0)); };
    const uint32_t w = code(d.x) | code(d.y) << 10 | code(d.z) << 20;
    std::memcpy(normals.data() + 4 * i, &w, 4);
    inputs[i] = glm::normalize(glm::dvec3((w & 1023) / 1023.0 * 2 - 1, ((w >> 10) & 1023) / 1023.0 * 2 - 1,
                                          ((w >> 20) & 1023) / 1023.0 * 2 - 1));
  }
  table() << "\n## normals.pack: LUT size vs error (" << inputs.size() << " directions, " << width << "x" << height
          << ")\n"
          << std::left << std::setw(12) << "lut" << std::right << std::setw(12) << "build ms" << std::setw(12)
          << "gpu ms" << std::setw(14) << "mean deg" << std::setw(12) << "max deg"
          << "\n";
  for (uint32_t lut_size : {64u, 256u, 1024u, 2048u}) {
    const double start = now_ms();
    std::vector<uint8_t> lut = nc::build_bfn_lut(lut_size);
    const double build = now_ms() - start;
    std::vector<double> times;
    nc::IsolatedRun run;
    for (int r = 0; r < 3; ++r) {
      run = nc::run_isolated(
          gpu, cache, nc::normals_pack_pass(),
          {{"gbuffer.normal", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, nc::kinds::normal, width, height, normals)},
           {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, nc::kinds::material, width, height, material)},
           {"normals.bfn_lut", image(VK_FORMAT_R8_UINT, nc::kinds::lookup_table, lut_size, lut_size, lut)}},
          {}, width, height, nc::builtin_shaders());
      times.push_back(gpu_ms(run));
    }
    const auto& packed = *run.outputs.at("normals.packed");
    double sum = 0, worst = 0;
    for (size_t i = 0; i < inputs.size(); ++i) {
      const uint8_t* c = packed.data() + 4 * i;
      const glm::dvec3 s =
          glm::normalize(glm::dvec3(nc::decode_signed8(c[0]), nc::decode_signed8(c[1]), nc::decode_signed8(c[2])));
      const double e = glm::degrees(std::atan2(glm::length(glm::cross(s, inputs[i])), glm::dot(s, inputs[i])));
      sum += e;
      worst = std::max(worst, e);
    }
    table() << std::left << std::setw(12) << lut_size << std::right << std::fixed << std::setprecision(1)
            << std::setw(12) << build << std::setprecision(3) << std::setw(12) << median(times) << std::setprecision(4)
            << std::setw(14) << sum / inputs.size() << std::setw(12) << worst << "\n";
    const std::string row = "normals_pack.lut_" + std::to_string(lut_size);
    figure(row + ".build_ms", build);
    figure(row + ".gpu_ms", median(times));
    figure(row + ".mean_deg", sum / inputs.size());
    figure(row + ".max_deg", worst);
  }
}

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
      const ref::Surface s = ref::make_surface(ref::reconstruct_position(constants, x, y, device_depth), normal_word,
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

// The built-in 16 km map, one shot at a time: cull.main alone (median of 5 runs on this
// thread, so one core: hierarchy walk, occlusion raster, tests and sort), then frames of the
// shot at the output size (the first one warms the pipelines; the camera walks), per pass.
void bench_map(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height, int repeats,
               bool frames) {
  for (nc::Shot shot : {nc::Shot::street, nc::Shot::rooftop, nc::Shot::aerial}) {
    const std::string name = nc::shot_name(shot);
    const nc::Scene scene = nc::build_map({1, 16.0, shot});
    const nc::Imports imports = nc::scene_imports(scene);
    std::map<std::string, nc::IsolatedInput> inputs;
    for (const char* resource :
         {"scene.instances", "scene.meshes", "scene.hierarchy", "scene.materials", "scene.geometry", "scene.decals"})
      inputs[resource] = {imports.at(resource).desc, imports.at(resource).bytes};
    const nc::ImportedData camera =
        nc::camera_import(*scene.camera, *scene.camera, width, height, 0, false).at("frame.camera");
    inputs["frame.camera"] = {camera.desc, camera.bytes};
    const nc::PassDecl cull = nc::cull_main_pass();
    std::vector<double> cull_ms;
    nc::CullStats stats{};
    for (int r = 0; r < 5; ++r) {
      nc::IsolatedRun run =
          nc::run_isolated(gpu, cache, cull, inputs, cull.default_params(), width, height, nc::builtin_shaders());
      cull_ms.push_back(run.execution.passes.at(0).cpu_ms);
      std::memcpy(&stats, run.outputs.at("cull.stats")->data(), sizeof(stats));
    }
    table() << "\n## map " << name << " shot (16 km, " << scene.instances.size() << " instances)\n"
            << "cull.main " << std::fixed << std::setprecision(3) << median(cull_ms)
            << " ms (median of 5): " << stats.visible << " visible, " << stats.culled_frustum << " culled by frustum, "
            << stats.culled_occlusion << " by occlusion, " << stats.culled_distance << " by distance; "
            << stats.occluders << " occluders (" << stats.occluder_triangles << " triangles); "
            << stats.draws_gbuffer + stats.draws_dynamic << " draws, "
            << stats.triangles_gbuffer + stats.triangles_dynamic << " triangles; levels of detail "
            << stats.lod_histogram[0] << "/" << stats.lod_histogram[1] << "/" << stats.lod_histogram[2] << "\n";
    figure("cull_ms_" + name, median(cull_ms));
    figure("instances_visible_" + name, stats.visible);
    figure("triangles_" + name, stats.triangles_gbuffer + stats.triangles_dynamic);
    figure("draws_" + name, stats.draws_gbuffer + stats.draws_dynamic);
    if (!frames) continue;
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.frames = uint32_t(repeats) + 1;
    nc::Renderer renderer(gpu, scene, settings);
    renderer.render_frame(0, false);
    std::map<std::string, std::vector<double>> pass_ms;
    std::vector<std::string> order;
    std::vector<double> frame_ms;
    for (int r = 1; r <= repeats; ++r) {
      const double start = now_ms();
      nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
      frame_ms.push_back(now_ms() - start);
      for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
        if (r == 1) order.push_back(frame.graph.passes[i].decl->name);
        if (!frame.graph.passes[i].runs) continue;
        const auto& exec = frame.execution.passes[i];
        pass_ms[frame.graph.passes[i].decl->name].push_back(exec.gpu_ms ? *exec.gpu_ms : exec.cpu_ms);
      }
    }
    table() << "frames at " << width << "x" << height << " (" << scene.lights.size() << " lights; median of " << repeats
            << ")\n";
    for (const std::string& pass : order) {
      table() << std::left << std::setw(22) << pass << std::right << std::setw(12);
      if (pass_ms[pass].empty())
        table() << "skipped";
      else
        table() << std::fixed << std::setprecision(3) << median(pass_ms[pass]);
      table() << "\n";
      if (!pass_ms[pass].empty()) figure("pass_ms.map_" + name + "." + pass, median(pass_ms[pass]));
    }
    table() << std::left << std::setw(22) << "frame" << std::right << std::setw(12) << median(frame_ms) << "\n";
    figure("frame_ms_" + name, median(frame_ms));
  }
}

// An empty scene (no mesh, no light): what a frame costs when there is nothing to draw. The
// second frame is measured (frame 0 compiles the pipelines); each repeat renders the next frame,
// the camera walking, with the history of the one before.
void bench_empty(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  const nc::Scene scene;
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  nc::Renderer renderer(gpu, scene, settings);
  std::vector<double> frame_ms;
  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<std::string> order;
  for (int r = 0; r <= repeats; ++r) {
    const double start = now_ms();
    const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
    if (r == 0) continue;
    frame_ms.push_back(now_ms() - start);
    for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
      const nc::CompiledPass& pass = frame.graph.passes[i];
      if (r == 1) order.push_back(pass.decl->name + (pass.runs ? "" : " (skipped: " + pass.reason + ")"));
      if (!pass.runs) continue;
      const auto& exec = frame.execution.passes[i];
      pass_ms[pass.decl->name].push_back(exec.gpu_ms ? *exec.gpu_ms : exec.cpu_ms);
    }
  }
  table() << "\n## empty scene at " << width << "x" << height << " (frames 1.." << repeats << ", median)\n";
  for (const std::string& line : order) {
    const std::string pass = line.substr(0, line.find(' '));
    table() << std::left << std::setw(22) << pass << std::right << std::setw(12);
    if (pass_ms[pass].empty())
      table() << line.substr(pass.size() + 1);
    else
      table() << std::fixed << std::setprecision(3) << median(pass_ms[pass]);
    table() << "\n";
  }
  table() << std::left << std::setw(22) << "frame" << std::right << std::setw(12) << median(frame_ms) << "\n";
  figure("frame_ms_empty", median(frame_ms));
}

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
          ms.push_back(frame.execution.passes[i].gpu_ms.value_or(0.0));
    }
    const nc::RenderedFrame captured = renderer.render_frame(uint32_t(repeats) + 1, true);
    std::map<std::string, nc::IsolatedInput> inputs;
    for (const char* name : {"frame.constants", "frame.lights", "depth.pyramid"}) {
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
      const std::string suffix = (extra ? "_" + std::to_string(extra) : "") + (key == "city" ? ".city" : "");
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
      const ref::Surface s = ref::make_surface(ref::reconstruct_position(constants, x, y, device_depth), normal_word,
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

// The mean length of the froxel list lighting.tiled reads per shaded pixel (drawn and not
// emission-only), from its recorded inputs: the slice of the pixel's linear depth by the shape
// lights.cluster recorded (cluster_layout.h's formula: a pixel on a slice bound may land one
// slice off the shader's, which moves the mean by nothing visible).
double mean_list_per_pixel(const std::map<std::string, nc::IsolatedInput>& inputs, const nc::GpuClusterStats& stats) {
  nc::GpuFrameConstants constants;
  std::memcpy(&constants, inputs.at("frame.constants").bytes->data(), sizeof constants);
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
      const uint32_t slice = nc::cluster_slice(metres, constants.projection_params.x, stats.max_distance, stats.slices);
      const size_t froxel = (size_t(slice) * tiles.height + y / stats.tile_size) * tiles.width + x / stats.tile_size;
      uint32_t count;
      std::memcpy(&count, clusters.bytes->data() + 8 * froxel + 4, 4);
      entries += count;
      ++pixels;
    }
  return pixels ? entries / double(pixels) : 0.0;
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

// decals.mesh and decals.projected against decal count on the reference scene of
// tests/reference/decal_reference.h: N projected boxes (the reference box, shifted and turned,
// grime) and N mesh decals (slabs on the ground), GPU ms as the median of `repeats` frames. The
// error figure is test 2's (tests/unit/decals_test.cpp): the largest distance between the box
// coordinate a coordinates decal writes into gbuffer.albedo and the ray-cast one, in metres along
// the box's axes, 10-bit quantisation included.
void bench_decals(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## decals (reference scene, " << width << "x" << height << ", median of " << repeats << ")\n"
          << std::left << std::setw(10) << "decals" << std::right << std::setw(18) << "decals.mesh ms" << std::setw(22)
          << "decals.projected ms\n";
  for (uint32_t count : {1u, 16u, 256u}) {
    nc::reference::DecalTestScene s = nc::reference::decal_test_scene();
    nc::scene_kit::Builder build(s.scene);
    nc::Material paint = nc::scene_kit::plain("decal.paint", {0.9f, 0.2f, 0.1f}, 0.0f, 0.5f, nc::stencil::plain);
    paint.base_color.a = 0.7f;
    paint.decal = true;
    const uint32_t slab = build.box({0.4f, 0.005f, 0.4f}, build.material(paint), 1.0f);
    std::mt19937 rng(count);
    std::uniform_real_distribution<double> spread(-4.0, 4.0), turn(0.0, 6.28);
    for (uint32_t k = 0; k < count; ++k) {
      nc::Decal decal;
      decal.world = glm::rotate(glm::translate(glm::dmat4(1.0), {spread(rng), 0.0, spread(rng)}), turn(rng),
                                glm::dvec3(0, 1, 0)) *
                    nc::reference::decal_test_box();
      decal.pattern = nc::DecalPattern::grime;
      decal.scale = 4.0f;
      s.scene.decals.push_back(decal);
      build.place(slab, {spread(rng), 0.005, spread(rng)}, turn(rng));
    }
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = nc::CameraPath::Motion::still;
    nc::Renderer renderer(gpu, s.scene, settings);
    std::map<std::string, std::vector<double>> ms;
    for (int r = 0; r <= repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
      for (size_t i = 0; r > 0 && i < frame.graph.passes.size(); ++i)
        if (frame.graph.passes[i].runs && frame.execution.passes[i].gpu_ms)
          ms[frame.graph.passes[i].decl->name].push_back(*frame.execution.passes[i].gpu_ms);
    }
    const double mesh = median(ms["decals.mesh"]), projected = median(ms["decals.projected"]);
    table() << std::left << std::setw(10) << count << std::right << std::fixed << std::setprecision(3) << std::setw(18)
            << mesh << std::setw(21) << projected << "\n";
    figure("decals_mesh_ms." + std::to_string(count), mesh);
    figure("decals_projected_ms." + std::to_string(count), projected);
    if (count == 256) {
      figure("decals_mesh_ms", mesh);
      figure("decals_projected_ms", projected);
    }
  }
  nc::reference::DecalTestScene s = nc::reference::decal_test_scene();
  nc::Decal decal;
  decal.world = nc::reference::decal_test_box();
  decal.pattern = nc::DecalPattern::coordinates;
  s.scene.decals.push_back(decal);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.path.motion = nc::CameraPath::Motion::still;
  nc::Renderer renderer(gpu, s.scene, settings);
  const nc::RenderedFrame frame = renderer.render_frame(0, true);
  const auto& albedo = *frame.execution.final_version("gbuffer.albedo")->bytes;
  const glm::dvec3 size(glm::length(decal.world[0]), glm::length(decal.world[1]), glm::length(decal.world[2]));
  double worst = 0.0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const auto hit = nc::reference::cast_pixel(s, frame.camera, width, height, x, y);
      if (!hit || hit->moving) continue;
      const glm::dvec3 local = nc::reference::decal_local(decal.world, hit->position);
      // Away from the faces (test 2's bound) and from silhouettes: one pixel's footprint.
      const double footprint = 2.0 * std::tan(double(frame.camera.yfov) / 2) / height * hit->distance;
      if (nc::reference::distance_to_faces(decal.world, hit->position) <= footprint ||
          !glm::all(glm::lessThanEqual(glm::abs(local), glm::dvec3(0.5))))
        continue;
      uint32_t word;
      std::memcpy(&word, albedo.data() + 4 * (size_t(y) * width + x), 4);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(((word >> (10 * c)) & 1023) / 1023.0 - (local[c] + 0.5)) * size[c]);
    }
  table() << "position error of a coordinates decal: " << std::setprecision(5) << worst * 1e3
          << " mm (10-bit quantisation of a " << size.x << " m box: " << 0.5 / 1023 * size.x * 1e3 << " mm)\n";
  figure("decals_position_error_m", worst);
}

// A stencil tag per pixel: every class and flag of passes/scene/scene.h, one pixel in 200 moving,
// hair or foliage (the rest plain, road, body, face or vehicle).
std::vector<uint8_t> bench_tags(size_t pixels, std::mt19937& rng) {
  namespace st = nc::stencil;
  const uint8_t untagged[] = {st::plain, st::road, st::body, st::face, st::vehicle};
  const uint8_t tagged[] = {st::hair, st::foliage, st::body | st::moving, st::vehicle | st::moving};
  std::vector<uint8_t> tags(pixels);
  for (uint8_t& t : tags)
    t = rng() % 200 == 0 ? tagged[rng() % std::size(tagged)] : untagged[rng() % std::size(untagged)];
  return tags;
}

// depth.convert and depth.pyramid: time, and error against double-precision / exact references;
// depth.convert's time covers its three outputs (depth.linear, depth.half, stencil.half), which
// one dispatch writes.
void bench_depth(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(7);
  std::vector<float> device_depth(size_t(width) * height);
  for (float& d : device_depth) d = float(rng() % 1000000 + 1) * 1e-6f;
  const std::vector<uint8_t> tags = bench_tags(device_depth.size(), rng);
  std::vector<uint8_t> depth_bytes(device_depth.size() * 5, 0);
  std::memcpy(depth_bytes.data(), device_depth.data(), device_depth.size() * 4);
  std::memcpy(depth_bytes.data() + device_depth.size() * 4, tags.data(), tags.size());
  nc::GpuFrameConstants constants{};
  constants.projection_params.x = 0.05f;
  const nc::IsolatedInput constants_in = constants_input(constants);
  std::vector<double> times, wall;
  nc::IsolatedRun convert;
  for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
    const double start = now_ms();
    convert = nc::run_isolated(
        gpu, cache, nc::depth_convert_pass(),
        {{"frame.constants", constants_in},
         {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, nc::kinds::depth_stencil, width, height, depth_bytes)}},
        nc::depth_convert_pass().default_params(), width, height, nc::builtin_shaders());
    if (r > 0) wall.push_back(now_ms() - start);
    if (r > 0) times.push_back(gpu_ms(convert));
  }
  const auto& linear = *convert.outputs.at("depth.linear");
  double worst = 0;
  for (size_t i = 0; i < device_depth.size(); ++i) {
    float v;
    std::memcpy(&v, linear.data() + 4 * i, 4);
    const double exact = double(0.05f) / double(device_depth[i]);
    worst = std::max(worst, std::abs(v - exact) / exact);
  }
  // The half outputs against tests/reference/depth_half_reference.h: depth error in half ULPs of
  // the exact value (the unit test bounds it by 0.5 plus a float ULP), stencil texels that differ.
  const ref::HalfDepthStencil half = ref::half_depth_stencil(device_depth, tags, width, height, double(0.05f),
                                                             nc::depth_convert_pass().default_params().at("sky_depth"));
  const auto& half_depth = *convert.outputs.at("depth.half");
  const auto& half_stencil = *convert.outputs.at("stencil.half");
  double worst_half_ulps = 0;
  size_t stencil_wrong = 0;
  for (size_t i = 0; i < half.metres.size(); ++i) {
    uint16_t bits;
    std::memcpy(&bits, half_depth.data() + 2 * i, 2);
    const double exact = half.metres[i];
    const double ulp = std::ldexp(1.0, std::max(std::ilogb(exact), -14) - 10);
    worst_half_ulps = std::max(worst_half_ulps, std::abs(nc::half_to_float(bits) - exact) / ulp);
    stencil_wrong += half_stencil[i] != half.stencil[i];
  }
  // lavapipe's timestamps around this one compute dispatch come out far below its work (hundredths
  // of a millisecond, against about 16 in the city frame), so the isolated run's wall clock is
  // printed too: an upper bound, with the upload of the inputs and the readback of the outputs.
  table() << "\n## depth (" << width << "x" << height << ")\n"
          << "depth.convert   gpu " << std::fixed << std::setprecision(3) << median(times) << " ms (timestamps), "
          << median(wall) << " ms isolated wall clock, max rel error vs double " << std::scientific
          << std::setprecision(2) << worst << "; depth.half max " << std::fixed << std::setprecision(4)
          << worst_half_ulps << " half ULP, stencil.half " << stencil_wrong << " texels differ\n";
  figure("depth_convert.gpu_ms", median(times));
  figure("depth_convert.isolated_wall_ms", median(wall));
  figure("depth_convert.max_rel_err", worst);
  figure("depth_convert.half_max_half_ulps", worst_half_ulps);
  figure("depth_convert.stencil_half_mismatches", double(stencil_wrong));
  times.clear();
  nc::IsolatedRun pyramid;
  for (int r = 0; r < 3; ++r) {
    pyramid = nc::run_isolated(
        gpu, cache, nc::depth_pyramid_pass(),
        {{"depth.linear", {convert.output_descs.at("depth.linear"), convert.outputs.at("depth.linear")}}}, {}, width,
        height, nc::builtin_shaders());
    times.push_back(gpu_ms(pyramid));
  }
  table() << "depth.pyramid   gpu " << std::fixed << std::setprecision(3) << median(times)
          << " ms, exact by construction (tests/unit/depth_pyramid_test.cpp)\n";
  figure("depth_pyramid.gpu_ms", median(times));
}

// scene.geometry's positions against the bits they keep: a scene's vertices quantised on the CPU
// in their primitives' boxes with 8, 10, 12 and 16 bits per axis (16 ships), the distance to the
// float position in object-space millimetres (max, mean over vertices), the time to quantise
// them, and the bytes a vertex would take (positions in 4 bytes up to 10 bits, else 8; the other
// streams' 20 bytes as shipped). Then the shipped buffer against the 72-byte float layout. The
// built-in city is boxes whose corners are their bounds, exact at any bit count; DamagedHelmet
// shows a curve.
void bench_vertex_streams(const std::string& key, const std::string& label, const nc::Scene& scene) {
  const nc::PackedGeometry packed = nc::pack_geometry(scene);
  std::vector<const nc::PositionBox*> box_of(scene.vertices.size(), nullptr);
  for (size_t p = 0; p < scene.primitives.size(); ++p)
    for (uint32_t k = 0; k < scene.primitives[p].index_count; ++k)
      box_of[size_t(scene.primitives[p].vertex_offset) + scene.indices[scene.primitives[p].first_index + k]] =
          &packed.boxes[p];
  table() << "\n## vertex streams: " << label << ", " << scene.vertices.size() << " vertices\n"
          << "position bits  bytes/vertex  max mm     mean mm    quantise ms\n";
  const uint32_t other_streams = nc::kVertexStreamBytes[nc::uv0_stream] + nc::kVertexStreamBytes[nc::frame_stream] +
                                 nc::kVertexStreamBytes[nc::color_uv1_stream];
  for (uint32_t bits : {8u, 10u, 12u, 16u}) {
    const uint32_t levels = (1u << bits) - 1;
    std::vector<double> times;
    double worst = 0, sum = 0;
    size_t counted = 0;
    for (int r = 0; r < 5; ++r) {
      worst = sum = 0;
      counted = 0;
      const double start = now_ms();
      for (size_t v = 0; v < scene.vertices.size(); ++v) {
        if (!box_of[v]) continue;
        const glm::vec3 step = nc::position_step(box_of[v]->min, box_of[v]->max, levels);
        glm::dvec3 error;
        for (int k = 0; k < 3; ++k) {
          const float p = scene.vertices[v].position[k], origin = box_of[v]->min[k];
          error[k] = nc::dequantise_position(nc::quantise_position(p, origin, step[k], levels), origin, step[k]) - p;
        }
        worst = std::max(worst, glm::length(error));
        sum += glm::length(error);
        ++counted;
      }
      times.push_back(now_ms() - start);
    }
    const uint32_t bytes = (bits <= 10 ? 4 : 8) + other_streams;
    const std::string row = "vertex_streams." + key + ".position_bits_" + std::to_string(bits);
    table() << std::setw(13) << bits << std::setw(14) << bytes << "  " << std::scientific << std::setprecision(3)
            << worst * 1e3 << "  " << sum / std::max<size_t>(counted, 1) * 1e3 << "  " << std::fixed
            << std::setprecision(3) << median(times) << "\n";
    figure(row + ".bytes_per_vertex", bytes);
    figure(row + ".max_mm", worst * 1e3);
    figure(row + ".mean_mm", sum / std::max<size_t>(counted, 1) * 1e3);
    figure(row + ".quantise_ms", median(times));
  }
  nc::GeometryHeader header;
  std::memcpy(&header, packed.bytes.data(), sizeof(header));
  const double vertex_bytes = double(header.index_offset - header.stream_offset[nc::position_stream]);
  const double float_layout = 72.0 * scene.vertices.size();
  const double float_buffer = nc::kGeometryAlignment +
                              std::ceil(float_layout / nc::kGeometryAlignment) * nc::kGeometryAlignment +
                              4.0 * scene.indices.size();
  std::vector<double> times;
  for (int r = 0; r < 5; ++r) {
    const double start = now_ms();
    const nc::PackedGeometry again = nc::pack_geometry(scene);
    times.push_back(now_ms() - start);
  }
  table() << "vertex streams " << std::setprecision(0) << vertex_bytes << " bytes (72-byte floats: " << float_layout
          << "), ratio " << std::setprecision(3) << vertex_bytes / float_layout << "; scene.geometry "
          << packed.bytes.size() << " bytes, ratio " << packed.bytes.size() / float_buffer << "; pack_geometry "
          << median(times) << " ms; G-buffer pass time: pass_ms." << key << ".gbuffer.opaque\n";
  figure("vertex_streams." + key + ".vertex_bytes_ratio", vertex_bytes / float_layout);
  figure("vertex_streams." + key + ".geometry_bytes_ratio", packed.bytes.size() / float_buffer);
  figure("vertex_streams." + key + ".pack_ms", median(times));
}

// motion.stencil: time against the dilation radius (timestamps and the isolated run's wall clock,
// as for depth.convert), and texels that differ from the brute-force CPU dilation of
// tests/reference/motion_mask_reference.h (the unit test requires none).
void bench_motion_stencil(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(11);
  const std::vector<uint8_t> tags = bench_tags(size_t(width) * height, rng);
  std::vector<uint8_t> depth_bytes(tags.size() * 5, 0);
  std::memcpy(depth_bytes.data() + tags.size() * 4, tags.data(), tags.size());
  const nc::IsolatedInput depth =
      image(VK_FORMAT_D32_SFLOAT_S8_UINT, nc::kinds::depth_stencil, width, height, depth_bytes);
  table() << "\n## motion.stencil (" << width << "x" << height << ", 1 pixel in 200 tagged)\n";
  for (int radius : {0, 2, 4, 8}) {
    std::vector<double> times, wall;
    nc::IsolatedRun run;
    for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
      const double start = now_ms();
      run = nc::run_isolated(gpu, cache, nc::motion_stencil_pass(), {{"scene.depth", depth}},
                             {{"radius", double(radius)}}, width, height, nc::builtin_shaders());
      if (r > 0) wall.push_back(now_ms() - start);
      if (r > 0) times.push_back(gpu_ms(run));
    }
    const std::vector<uint8_t> expected = ref::motion_mask(tags, width, height, radius);
    const auto& mask = *run.outputs.at("motion.mask");
    size_t wrong = 0, masked = 0;
    for (size_t i = 0; i < expected.size(); ++i) {
      wrong += mask[i] != expected[i];
      masked += expected[i];
    }
    table() << "radius " << radius << "   gpu " << std::fixed << std::setprecision(3) << median(times)
            << " ms (timestamps), " << median(wall) << " ms isolated wall clock, " << std::setprecision(1)
            << 100.0 * double(masked) / double(expected.size()) << "% masked, " << wrong
            << " texels differ from the CPU dilation\n";
    const std::string row = "motion_stencil.radius" + std::to_string(radius);
    figure(row + ".gpu_ms", median(times));
    figure(row + ".isolated_wall_ms", median(wall));
    figure(row + ".mismatches", double(wrong));
  }
}

// bloom: the six level passes as one graph on an HDR image of the output size (a night scene's
// range: dim surroundings, neon a few hundred times brighter), time summed over the levels, and
// the largest relative error of a level against the double-precision filter of the level above
// as stored (half a half-ULP is 4.9e-4) and of the chain against the filter applied all the way
// down without rounding (tests/unit/bloom_test.cpp bounds both).
void bench_bloom(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exponent(-10.0f, 9.0f), unit(0.0f, 1.0f);
  auto lit = std::make_shared<std::vector<uint8_t>>(size_t(width) * height * 8);
  ref::RgbImage exact_above{width, height, std::vector<std::array<double, 3>>(size_t(width) * height)};
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const bool neon = unit(rng) < 0.01f;
    uint16_t h[4] = {0, 0, 0, nc::float_to_half(1.0f)};
    for (int c = 0; c < 3; ++c) {
      h[c] = nc::float_to_half(neon ? 400.0f * unit(rng) : std::exp2(exponent(rng)));
      exact_above.texels[i][c] = nc::half_to_float(h[c]);
    }
    std::memcpy(lit->data() + 8 * i, h, 8);
  }
  std::vector<nc::PassDecl> passes;
  for (uint32_t level = 0; level < nc::kBloomLevels; ++level)
    passes.push_back(nc::bloom_level_pass(level, "lighting.lit"));
  nc::ResourceDesc desc;
  desc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
  desc.kind = nc::kinds::hdr_colour;
  desc.extent.width = width;
  desc.extent.height = height;
  nc::GraphSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"bloom.chain"};
  settings.readback = {"bloom.chain"};
  nc::ExecutionOptions options;
  options.shaders = nc::builtin_shaders();
  // lavapipe's timestamps around these compute passes come out far below the work they do (the
  // frame's figures show it too), so the wall-clock cost is measured as well: the same graph
  // with every level skipped (the chain only cleared) is the baseline.
  nc::GraphSettings skipped = settings;
  for (uint32_t level = 0; level < nc::kBloomLevels; ++level)
    skipped.params["bloom.level" + std::to_string(level)]["enabled"] = 0;
  std::vector<double> times, with_ms, without_ms;
  nc::Execution execution;
  for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
    nc::CompiledGraph graph = nc::compile_graph(passes, {{"lighting.lit", desc}}, settings);
    double start = now_ms();
    execution = nc::execute_graph(gpu, cache, graph, {{"lighting.lit", lit}}, options);
    if (r > 0) with_ms.push_back(now_ms() - start);
    double ms = 0;
    for (const auto& pass : execution.passes) ms += pass.gpu_ms.value_or(0.0);
    if (r > 0) times.push_back(ms);
    nc::CompiledGraph baseline = nc::compile_graph(passes, {{"lighting.lit", desc}}, skipped);
    start = now_ms();
    nc::execute_graph(gpu, cache, baseline, {{"lighting.lit", lit}}, options);
    if (r > 0) without_ms.push_back(now_ms() - start);
  }
  const double wall_ms = median(with_ms) - median(without_ms);
  const nc::VersionData& chain = *execution.final_version("bloom.chain");
  double level_err = 0, chain_err = 0;
  for (uint32_t level = 0; level < chain.desc.extent.mips; ++level) {
    const ref::RgbImage gpu_level = ref::decode_rgba16f(*chain.bytes, chain.desc.extent, level);
    const ref::RgbImage above =
        level == 0 ? exact_above : ref::decode_rgba16f(*chain.bytes, chain.desc.extent, level - 1);
    const ref::RgbImage exact = ref::bloom_level(above, gpu_level.width, gpu_level.height, 1.5);
    if (level == 0)
      exact_above = exact;
    else
      exact_above = ref::bloom_level(exact_above, gpu_level.width, gpu_level.height, 1.5);
    for (size_t i = 0; i < exact.texels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double g = gpu_level.texels[i][c];
        if (exact.texels[i][c] >= 0x1p-14)
          level_err = std::max(level_err, std::abs(g - exact.texels[i][c]) / exact.texels[i][c]);
        if (exact_above.texels[i][c] >= 0x1p-14)
          chain_err = std::max(chain_err, std::abs(g - exact_above.texels[i][c]) / exact_above.texels[i][c]);
      }
  }
  table() << "\n## bloom (" << width << "x" << height << " lit, " << chain.desc.extent.width << "x"
          << chain.desc.extent.height << " chain, " << chain.desc.extent.mips << " levels, sigma 1.5)\n"
          << "bloom.level0-5  gpu " << std::fixed << std::setprecision(3) << median(times) << " ms (timestamps), "
          << wall_ms << " ms wall-clock over the skipped chain, max rel error per level " << std::scientific
          << std::setprecision(2) << level_err << ", down the chain " << chain_err << "\n";
  figure("bloom.gpu_ms", median(times));
  figure("bloom.wall_ms", wall_ms);
  figure("bloom.max_rel_err", level_err);
  figure("bloom.chain_max_rel_err", chain_err);
}

// exposure: time, and the error of the histogram's mean log2 luminance (bin centres) against the
// exact mean over every pixel, for the default 24-EV range and a twice as wide, coarser one.
void bench_exposure(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> level(-10.0, 10.0);
  std::vector<uint16_t> texels;
  double exact = 0;
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const uint16_t h = nc::float_to_half(float(std::exp2(level(rng))));
    texels.insert(texels.end(), {h, h, h, 0x3c00});
    exact += std::log2(double(nc::half_to_float(h)) * (0.2126 + 0.7152 + 0.0722));
  }
  exact /= double(width) * height;
  std::vector<uint8_t> lit(texels.size() * 2);
  std::memcpy(lit.data(), texels.data(), lit.size());
  nc::GpuFrameConstants constants{};
  constants.timing.y = float(nc::kFrameSeconds);
  const nc::IsolatedInput constants_in = constants_input(constants);
  table() << "\n## exposure (" << width << "x" << height << ", log2 luminance uniform in [-10, 10])\n";
  for (const double range : {24.0, 48.0}) {
    nc::ParamValues params = nc::exposure_pass("lighting.lit").default_params();
    params["log2_min"] = -range / 2;
    params["log2_max"] = range / 2;
    std::vector<double> times;
    nc::IsolatedRun run;
    for (int r = 0; r < 3; ++r) {
      run = nc::run_isolated(
          gpu, cache, nc::exposure_pass("lighting.lit"),
          {{"frame.constants", constants_in},
           {"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, nc::kinds::hdr_colour, width, height, lit)},
           {nc::previous("exposure.value"),
            image(VK_FORMAT_R32G32B32A32_SFLOAT, nc::kinds::hdr_colour, 1, 1, std::vector<uint8_t>(16, 0))}},
          params, width, height, nc::builtin_shaders());
      times.push_back(gpu_ms(run));
    }
    float value[4];
    std::memcpy(value, run.outputs.at("exposure.value")->data(), sizeof value);
    const double error = std::abs(value[2] - exact);
    const std::string row = "exposure.range" + std::to_string(int(range));
    table() << row << "   gpu " << std::fixed << std::setprecision(3) << median(times) << " ms, |mean - exact| "
            << std::setprecision(5) << error << " EV (bin width " << range / nc::kExposureBins << " EV)\n";
    figure(row + ".gpu_ms", median(times));
    figure(row + ".err_ev", error);
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
      settings.params["shadow.cull"]["resolution"] = resolution;
      settings.params["shadow.cascades_static"]["resolution"] = resolution;
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

// `count` spot lights 8 m up, pointing down and ahead, 25 m range, spread over the first 60 m of
// the view of frame 0 (seeded): street lamps over the part of the scene the maps cover.
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

// The shadow passes with a `cache` parameter.
constexpr const char* kShadowCaches[] = {"shadow.cull", "shadow.distant_plan", "shadow.local_plan"};

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nightcap benchmark: per-pass GPU time, capture cost and size, time against error"};
  uint32_t repeats = 5, directions = 1 << 20;
  std::string size = "1280x720", device, data = NIGHTCAP_SHARED_DATA;
  bool skip_models = false, map_frames = true;
  std::vector<std::string> only;
  const std::vector<std::string> sections = {
      "city",    "models",       "map",           "empty",   "frames", "normals", "tubes",        "depth", "motion",
      "streams", "bloom",        "exposure",      "startup", "diff",   "report",  "decals",       "ltc",   "cluster",
      "tiled",   "tube_quality", "cluster_shape", "shadows", "tod",    "distant", "shadow_cache", "local"};
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
    if (g_json) std::cout << nlohmann::json{{"figures", g_figures}}.dump(1) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "nightcap_bench: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
