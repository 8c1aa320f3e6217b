// The CLI run as a person runs it: start-up, the debugger's first answer, diff against idiff, report; one blob read.
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "captures/blob_codec.h"
#include "captures/capture.h"
#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/scene/scene.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;
namespace fs = std::filesystem;

namespace nightcap::bench {

namespace {

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

uint64_t folder_bytes(const fs::path& folder) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

}  // namespace

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

}  // namespace nightcap::bench
