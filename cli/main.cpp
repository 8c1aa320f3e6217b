// nightcap: render a scene to a capture, list its passes, check every blob of it, replay them, diff two captures (or a
// capture and a golden of a store), keep goldens, draw a frame's graph, step through a capture
// pass by pass.
// Exit codes: 0 success, 1 differences beyond tolerance, 2 bad input or failure.
#include <malloc.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "captures/capture.h"
#include "captures/golden_store.h"
#include "cli/inspect_repl.h"
#include "compare/diff.h"
#include "compare/diff_results.h"
#include "compare/flip_map.h"
#include "inspect/capture_check.h"
#include "inspect/commands.h"
#include "inspect/graph_dot.h"
#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/core/shader.h"
#include "passes/scene/time_of_day.h"
#include "replay/isolate.h"
#include "replay/replay.h"
#include "reports/capture_report.h"
#include "reports/diff_report.h"
#include "reports/html.h"

namespace nc = nightcap;

namespace {

constexpr int kExitDifferent = 1;
constexpr int kExitBadInput = 2;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

bool validation_requested() {
  const char* value = std::getenv("NIGHTCAP_VALIDATION");
  return value && std::string(value) == "1";
}

std::pair<uint32_t, uint32_t> parse_size(const std::string& text) {
  // Each side: one or more digits and nothing else (strtoul alone accepts signs and spaces).
  auto side = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
      throw UsageError("--size '" + text + "': expected WIDTHxHEIGHT");
    return std::stoul(digits);
  };
  const size_t x = text.find('x');
  if (x == std::string::npos) throw UsageError("--size '" + text + "': expected WIDTHxHEIGHT");
  const unsigned long w = side(text.substr(0, x)), h = side(text.substr(x + 1));
  if (w == 0 || h == 0 || w > nc::kMaxImageSide || h > nc::kMaxImageSide)
    throw UsageError("--size '" + text + "': each side must be between 1 and " + std::to_string(nc::kMaxImageSide));
  return {uint32_t(w), uint32_t(h)};
}

std::vector<double> parse_numbers(const std::string& flag, const std::string& text, size_t count) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw UsageError(flag + " '" + text + "': not a number list");
    values.push_back(v);
  }
  if (values.size() != count)
    throw UsageError(flag + " '" + text + "': expected " + std::to_string(count) + " comma-separated numbers");
  return values;
}

volatile std::sig_atomic_t g_stop_signal = 0;

// SIGINT and SIGTERM stop a render between frames so that its temporary capture is removed
// (a SIGKILLed one is cleaned up by the next render of the same -o).
void stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = [](int signal) { g_stop_signal = signal; };
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

nc::RenderMonitor render_monitor() {
  nc::RenderMonitor monitor;
  if (isatty(STDERR_FILENO))
    monitor.progress = [](const std::string& line) { std::cerr << "\r\033[K" << line << std::flush; };
  monitor.stop_requested = [] { return g_stop_signal != 0; };
  return monitor;
}

std::string ms(const std::optional<double>& value) {
  if (!value) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << *value;
  return s.str();
}

struct RenderFlags {
  std::string scene_path, out, size = "1280x720", device, orbit, target, codec = "auto", motion = "walk", record, shot;
  uint32_t frames = 1, seed = 1;
  double map_size = 0.0;  // 0: not given
  double fov = 45.0;
  std::optional<double> hour;
  std::string tod;
  std::vector<std::string> sets, inject_nan;
  std::vector<uint32_t> cuts;
  bool force = false, city_block = false;
};

// "A..B" or "A": the frames to record, inclusive.
std::pair<uint32_t, uint32_t> parse_frame_range(const std::string& text, uint32_t frames) {
  const size_t dots = text.find("..");
  const std::string a = text.substr(0, dots), b = dots == std::string::npos ? a : text.substr(dots + 2);
  auto number = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
      throw UsageError("--record-frames '" + text + "': expected FIRST..LAST (frame indices from 0)");
    return uint32_t(std::stoul(digits));
  };
  const uint32_t first = number(a), last = number(b);
  if (first > last || last >= frames)
    throw UsageError("--record-frames '" + text + "': expected FIRST <= LAST < --frames (" + std::to_string(frames) +
                     ")");
  return {first, last};
}

int run_render(const RenderFlags& flags) {
  const std::string &scene_path = flags.scene_path, &size = flags.size, &orbit = flags.orbit, &target = flags.target,
                    &codec = flags.codec;
  const uint32_t frames = flags.frames, seed = flags.seed;
  const double fov = flags.fov;
  nc::RenderSettings settings;
  if (codec != "auto") {
    settings.capture.images = nc::image_encoding_by_name(codec);
    if (!settings.capture.images)
      throw UsageError("--codec '" + codec +
                       "': expected auto, none, rle, zips, zip, piz or pxr24 (zip1 … zip9: a zlib level)");
  }
  std::tie(settings.width, settings.height) = parse_size(size);
  if (frames < 1 || frames > 1000) throw UsageError("--frames " + std::to_string(frames) + ": expected 1 to 1000");
  settings.frames = frames;
  settings.path.motion = nc::CameraPath::parse_motion(flags.motion);
  for (uint32_t cut : flags.cuts) {
    if (cut == 0 || cut >= frames)
      throw UsageError("--cut-at " + std::to_string(cut) + ": expected a frame from 1 to " +
                       std::to_string(frames - 1) + " (frame 0 has no history to cut)");
    settings.path.cuts.insert(cut);
  }
  if (!flags.record.empty())
    std::tie(settings.first_recorded, settings.last_recorded) = parse_frame_range(flags.record, frames);
  for (const std::string& s : flags.sets) nc::parse_set(nc::frame_passes(), s, settings.params);
  for (const std::string& text : flags.inject_nan) settings.inject_nan.push_back(nc::parse_inject_nan(text));
  nc::validate_nan_requests(nc::frame_passes(), settings.inject_nan, settings.width, settings.height);
  if (!orbit.empty()) {
    auto o = parse_numbers("--orbit", orbit, 3);
    auto t = target.empty() ? std::vector<double>{0, 0, 0} : parse_numbers("--target", target, 3);
    if (o[2] <= 0) throw UsageError("--orbit: radius must be positive");
    if (!(fov > 0 && fov < 180)) throw UsageError("--fov: expected degrees in (0, 180)");
    settings.camera = nc::orbit_camera(o[0], o[1], o[2], {t[0], t[1], t[2]}, fov);
  } else if (!target.empty()) {
    throw UsageError("--target needs --orbit");
  }
  const bool map_flags = !flags.shot.empty() || flags.map_size != 0.0;
  if (map_flags && !scene_path.empty())
    throw UsageError("--shot and --map-size choose the built-in map, not a glTF scene");
  if (flags.city_block && !scene_path.empty()) throw UsageError("--city-block is a built-in scene, not a glTF scene");
  if (!flags.tod.empty() && (!scene_path.empty() || flags.city_block))
    throw UsageError("--tod: a time-of-day table is baked for the built-in map (`nightcap bake-tod`), not for " +
                     (flags.city_block ? std::string("the city block") : scene_path));
  nc::Scene scene;
  nc::MapOptions options;
  if (!scene_path.empty()) {
    scene = nc::load_gltf(scene_path);
  } else if (flags.city_block) {
    scene = nc::build_city(seed);
  } else {
    options.seed = seed;
    if (flags.map_size != 0.0) options.size_km = flags.map_size;
    if (!flags.shot.empty()) options.shot = nc::parse_shot(flags.shot);
    scene = nc::build_map(options);
  }
  if (flags.hour) nc::set_hour(scene, *flags.hour);
  if (!flags.tod.empty()) {
    scene.tod_visible = nc::read_tod(flags.tod, options.seed, options.size_km, scene).visible;
    scene.tod_hour = *flags.hour;
  }
  nc::add_default_lighting(scene);
  settings.description = {{"width", settings.width},
                          {"height", settings.height},
                          {"frames", frames},
                          {"scene", !scene_path.empty() ? scene_path
                                    : flags.city_block  ? "built-in city block"
                                                        : "built-in map"},
                          {"scene_seed", seed},
                          {"shot", flags.shot},
                          {"map_size_km", flags.map_size},
                          {"set", flags.sets},
                          {"motion", flags.motion},
                          {"cut_at", flags.cuts},
                          {"record_frames", flags.record},
                          {"orbit", orbit},
                          {"target", target},
                          {"fov", fov},
                          {"codec", codec},
                          {"inject_nan", flags.inject_nan}};
  if (flags.hour) settings.description["hour"] = *flags.hour;
  if (!flags.tod.empty()) settings.description["tod"] = flags.tod;
  nc::GpuDevice gpu({flags.device, validation_requested()});
  stop_on_signals();
  nc::RenderSummary summary = nc::render_to_capture(gpu, scene, settings, flags.out, flags.force, render_monitor());
  if (isatty(STDERR_FILENO)) std::cerr << "\r\033[K";
  const uint32_t recorded = std::min(settings.last_recorded, frames - 1) - settings.first_recorded + 1;
  std::cout << "capture written to " << flags.out << " (" << recorded << " frame" << (recorded > 1 ? "s" : "") << ", "
            << gpu.name() << ", " << std::fixed << std::setprecision(1) << summary.disk_bytes / 1048576.0
            << " MiB on disk)\n";
  return 0;
}

int run_bake_tod(uint32_t seed, double size_km, const std::string& out) {
  const auto start = std::chrono::steady_clock::now();
  const nc::Scene scene = nc::build_map({seed, size_km, nc::Shot::street});
  const nc::TodTable table = nc::bake_tod(scene, seed, size_km);
  nc::write_tod(table, out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "time-of-day table written to " << out << " (" << table.visible.size() << " instances, latitude "
            << nc::kTodLatitudeDegrees << "° N, equinox; " << std::fixed << std::setprecision(1) << seconds
            << " s)\nstatic casters hidden from the light at each baked hour:";
  for (uint32_t slot = 0; slot < nc::kTodHours; ++slot) {
    size_t hidden = 0;
    for (uint16_t bits : table.visible) hidden += !(bits >> slot & 1);
    std::cout << (slot % 6 ? ", " : "\n  ") << std::setw(2) << std::setfill('0') << slot * 2 << ":00 "
              << std::setfill(' ') << hidden;
  }
  std::cout << "\n";
  return 0;
}

int run_passes(const std::string& path, bool json) {
  const nc::Capture capture = nc::Capture::open(path);
  if (json) {
    const nlohmann::json out = {{"frames", nc::to_json(capture.manifest()).at("frames")}};
    std::cout << out.dump(1) << "\n";
    return 0;
  }
  for (const nc::FrameRecord& frame : capture.manifest().frames) {
    std::cout << "frame " << frame.index << " at " << std::fixed << std::setprecision(3) << frame.time << " s"
              << (frame.camera_cut ? ", camera cut" : "");
    for (const auto& [resource, reason] : frame.history_reset)
      std::cout << "; history of " << resource << " restarted (" << reason << ")";
    std::cout << "\n";
    std::cout << std::left << std::setw(22) << "  pass" << std::setw(9) << "status" << std::right << std::setw(10)
              << "gpu ms" << std::setw(10) << "cpu ms"
              << "  outputs\n";
    for (const nc::PassRecord& p : frame.passes) {
      std::cout << "  " << std::left << std::setw(20) << p.name << std::setw(9) << (p.ran ? "ran" : "skipped")
                << std::right << std::setw(10) << ms(p.gpu_ms) << std::setw(10) << ms(p.cpu_ms) << "  ";
      if (!p.ran) std::cout << "(" << p.reason << ") ";
      for (const nc::ResourceRecord& o : p.outputs) {
        std::cout << o.resource << " ";
        if (o.is_buffer)
          std::cout << "[" << o.buffer_size << " B] ";
        else
          std::cout << "[" << nc::format_info(o.format)->name << " " << o.extent.width << "x" << o.extent.height
                    << (o.extent.mips > 1 ? " mips " + std::to_string(o.extent.mips) : "") << "] ";
      }
      std::cout << "\n";
    }
  }
  return 0;
}

int run_replay(const std::string& path, uint32_t frame, const std::vector<std::string>& pass_names,
               const std::vector<std::string>& sets, const std::vector<std::string>& shaders, const std::string& device,
               bool verify, bool chain, bool json) {
  nc::ReplayOptions options;
  options.frame = frame;
  options.passes = pass_names;
  options.chain = chain;
  for (const std::string& s : sets) nc::parse_set(nc::all_passes(), s, options.params);
  for (const std::string& s : shaders) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw UsageError("--shader '" + s + "': expected PASS=FILE");
    options.shader_files[s.substr(0, eq)] = s.substr(eq + 1);
  }
  const nc::Capture capture = nc::Capture::open(path);
  nc::GpuDevice gpu({device, validation_requested()});
  const nc::ReplayReport report = nc::replay_capture(gpu, capture, options);
  if (json) {
    nlohmann::json out = {{"frame", report.frame}, {"device", report.device}, {"passes", nlohmann::json::array()}};
    for (const nc::PassReplay& p : report.passes) {
      nlohmann::json pass = {{"name", p.name}, {"replayed", p.replayed}, {"notes", p.notes}};
      if (!p.replayed) pass["reason"] = p.reason;
      pass["gpu_ms"] = p.gpu_ms ? nlohmann::json(*p.gpu_ms) : nlohmann::json(nullptr);
      pass["cpu_ms"] = p.cpu_ms;
      if (verify) {
        pass["outputs"] = nlohmann::json::array();
        for (const nc::OutputCheck& o : p.outputs) {
          pass["outputs"].push_back({{"resource", o.resource},
                                     {"verdict", nc::verdict_name(o.verdict)},
                                     {"metric", o.metric},
                                     {"max_abs", o.amount},
                                     {"recorded_hash", o.recorded_hash},
                                     {"replayed_hash", o.replayed_hash}});
          if (!o.first_difference.empty()) pass["outputs"].back()["first_difference"] = o.first_difference;
          if (o.contract)
            pass["outputs"].back()["contract"] = {{"holds", o.contract->holds},
                                                  {"worst", o.contract->worst},
                                                  {"bound", o.contract->bound},
                                                  {"measure", o.contract->measure}};
        }
      }
      out["passes"].push_back(pass);
    }
    out["different"] = verify && report.any_different();
    std::cout << out.dump(1) << "\n";
  } else {
    std::cout << "replay of frame " << report.frame << " on " << report.device << "\n";
    for (const nc::PassReplay& p : report.passes) {
      std::cout << "  " << std::left << std::setw(20) << p.name;
      if (!p.replayed) {
        std::cout << "not replayed: " << p.reason << "\n";
        continue;
      }
      std::cout << "gpu " << ms(p.gpu_ms) << " ms, cpu " << ms(p.cpu_ms) << " ms\n";
      for (const std::string& note : p.notes) std::cout << "      note: " << note << "\n";
      if (!verify) continue;
      for (const nc::OutputCheck& o : p.outputs) {
        std::cout << "      " << std::left << std::setw(24) << o.resource << nc::verdict_name(o.verdict);
        if (o.verdict != nc::Verdict::identical)
          std::cout << " (" << o.metric << ", max abs " << o.amount
                    << (o.first_difference.empty() ? "" : ", first at " + o.first_difference) << ")";
        std::cout << "\n";
      }
    }
    if (verify)
      std::cout << (report.any_different() ? "replay differs from the capture\n" : "replay matches the capture\n");
  }
  return verify && report.any_different() ? kExitDifferent : 0;
}

// Exit 0 when every blob the manifest names reads, decodes and matches its hash; 2 when any does
// not, as for a manifest that cannot be read.
int run_check(const std::string& path, bool json) {
  const auto start = std::chrono::steady_clock::now();
  const nc::Capture capture = nc::Capture::open(path);
  const nc::CaptureCheck check = nc::check_capture(capture);
  if (json) {
    nlohmann::json out = nc::to_json(check);
    out["capture"] = path;
    std::cout << out.dump(1) << "\n";
    return check.bad.empty() ? 0 : kExitBadInput;
  }
  constexpr size_t kReferencesShown = 3;
  for (const nc::BadBlob& bad : check.bad) {
    std::cout << bad.blob << ": " << nc::blob_problem_name(bad.check.problem) << "\n  " << bad.check.detail << "\n";
    for (size_t i = 0; i < std::min(bad.references.size(), kReferencesShown); ++i)
      std::cout << "  " << nc::describe(bad.references[i]) << "\n";
    if (bad.references.size() > kReferencesShown)
      std::cout << "  and " << bad.references.size() - kReferencesShown << " more\n";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "checked " << check.blobs << " blobs (" << std::fixed << std::setprecision(1)
            << check.bytes_on_disk / 1048576.0 << " MiB) in " << std::setprecision(2) << seconds << " s: ";
  if (check.bad.empty())
    std::cout << "every blob reads, decodes and matches its hash\n";
  else
    std::cout << check.bad.size() << " bad\n";
  return check.bad.empty() ? 0 : kExitBadInput;
}

struct DiffFlags {
  std::string thresholds, junit;
  std::optional<double> tolerance;
  std::optional<uint32_t> frame;
  bool json = false;
  bool isolate = false;
  std::string device;  // of --isolate's replays
  std::string flip_maps;
  std::optional<std::string> golden;  // capture A is this golden of `store`
  std::string store;
};

void check_golden_name(const std::string& flag, const std::string& name) {
  if (!nc::safe_name(name))
    throw UsageError(flag + " '" + name +
                     "': not a golden name (printable characters, no spaces, '/' or '\\', not . or ..)");
}

// A golden that is not there is its own result: the first run of a CI job, say, which has to
// record it.
nc::Capture open_golden(const DiffFlags& flags, const std::string& capture) {
  const std::string& name = *flags.golden;
  check_golden_name("--golden", name);
  if (std::filesystem::exists(flags.store)) {
    const nc::GoldenStore store = nc::GoldenStore::open(flags.store);
    if (store.contains(name)) return store.golden(name);
  }
  throw UsageError("golden '" + name + "' missing from store " + flags.store +
                   " (record it with: nightcap golden update " + capture + " --store " + flags.store + " --name " +
                   name + ")");
}

// What the diff flags ask of diff_captures; `thresholds` keeps the rules of --thresholds.
nc::DiffOptions diff_options(const DiffFlags& flags, nc::Thresholds& thresholds) {
  nc::DiffOptions options;
  options.golden = flags.golden.has_value();
  if (!flags.thresholds.empty()) {
    thresholds = nc::read_thresholds(flags.thresholds);
    options.thresholds = &thresholds;
  }
  options.tolerance = flags.tolerance;
  options.frame = flags.frame;
  return options;
}

// Exit 0 when every result is within what it was held to, 1 when one is not; the last line
// counts them (on stderr when --json owns stdout). With a golden, `a` is unused: the golden is
// capture A, the reference.
int run_diff(const std::string& a, const std::string& b, const DiffFlags& flags) {
  const auto start = std::chrono::steady_clock::now();
  const nc::Capture capture_a = flags.golden ? open_golden(flags, b) : nc::Capture::open(a);
  const nc::Capture capture_b = nc::Capture::open(b);
  nc::Thresholds thresholds;
  nc::CaptureDiff diff = nc::diff_captures(capture_a, capture_b, diff_options(flags, thresholds));
  if (flags.isolate) {
    nc::GpuDevice gpu({flags.device, validation_requested()});
    nc::isolate_passes(gpu, capture_a, capture_b, diff);
  }
  if (!flags.flip_maps.empty()) nc::write_flip_maps(diff, flags.flip_maps);
  const std::vector<nc::DiffCase> cases = nc::diff_cases(diff);
  const nc::DiffTally counts = nc::tally(cases);
  if (!flags.junit.empty())
    nc::write_junit(flags.junit, cases,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (flags.json)
    std::cout << nc::diff_to_json(diff).dump(1) << "\n";
  else
    nc::print_diff_table(std::cout, diff);
  (flags.json ? std::cerr : std::cout) << counts.passed << " passed, " << counts.failed << " failed\n";
  return counts.failed > 0 ? kExitDifferent : 0;
}

int run_golden_update(const std::string& capture, const std::string& store, const std::string& name) {
  check_golden_name("--name", name);
  const nc::GoldenUpdate update = nc::GoldenStore::update(store, capture, name);
  std::cout << "golden '" << name << "' updated in " << store << " from " << update.golden.source << " ("
            << update.blobs_copied << " blobs copied, " << update.blobs_shared << " already in the store)\n";
  return 0;
}

int run_golden_list(const std::string& store_dir, bool json) {
  const nc::GoldenStore store = nc::GoldenStore::open(store_dir);
  const std::vector<nc::GoldenInfo> goldens = store.list();
  if (json) {
    nlohmann::json out = {{"store", store.root().string()}, {"goldens", nlohmann::json::array()}};
    for (const nc::GoldenInfo& g : goldens)
      out["goldens"].push_back(
          {{"name", g.name}, {"frames", g.frames}, {"passes", g.passes}, {"source", g.source}, {"updated", g.updated}});
    std::cout << out.dump(1) << "\n";
    return 0;
  }
  std::cout << std::left << std::setw(24) << "name" << std::right << std::setw(7) << "frames" << std::setw(8)
            << "passes"
            << "  " << std::left << std::setw(22) << "updated"
            << "source\n";
  for (const nc::GoldenInfo& g : goldens)
    std::cout << std::left << std::setw(24) << g.name << std::right << std::setw(7) << g.frames << std::setw(8)
              << g.passes << "  " << std::left << std::setw(22) << g.updated << g.source << "\n";
  return 0;
}

int run_graph(const std::string& path, uint32_t frame, const std::string& output) {
  const nc::Capture capture = nc::Capture::open(path);
  const nc::FrameRecord* record = nullptr;
  try {
    record = &capture.frame(frame);
  } catch (const nc::CaptureError& e) {
    throw UsageError("--frame " + std::to_string(frame) + ": " + e.what());
  }
  const std::string dot = nc::frame_to_dot(*record);
  if (output.empty()) {
    std::cout << dot;
    return 0;
  }
  std::ofstream file(output, std::ios::binary | std::ios::trunc);
  file << dot;
  file.close();
  if (!file) throw UsageError(output + ": cannot write");
  return 0;
}

// A folder `report --force` may replace: empty, or holding a report nightcap wrote (its
// index.html says so), never any other folder.
bool replaceable_report(const std::filesystem::path& folder) {
  if (std::filesystem::is_empty(folder)) return true;
  std::ifstream index(folder / "index.html");
  std::string head(512, '\0');
  index.read(head.data(), std::streamsize(head.size()));
  return head.find(nc::kReportGenerator) != std::string::npos;
}

// Empties `output` for a report: it must not exist or be empty, or with --force hold a report.
void prepare_report_folder(const std::string& output, bool force) {
  const std::filesystem::path folder(output);
  if (!std::filesystem::exists(folder) || std::filesystem::is_empty(folder)) return;
  if (!force) throw UsageError(output + ": exists and is not empty (--force replaces an earlier report)");
  if (!replaceable_report(folder))
    throw UsageError(output + ": --force replaces only a folder holding a nightcap report, and this is not one");
  std::filesystem::remove_all(folder);
}

// One capture: its report. Two (or a golden and one): the report of their diff, with the diff's
// flags; it exits 0 once written, whatever the diff found (`diff` is the command that gates).
int run_report(const std::string& a, const std::string& b, const DiffFlags& flags, const std::string& output,
               bool force) {
  const bool of_diff = flags.golden || !b.empty();
  const nc::Capture capture = flags.golden ? open_golden(flags, a) : nc::Capture::open(a);
  if (flags.frame) {
    try {
      capture.frame(*flags.frame);
    } catch (const nc::CaptureError& e) {
      throw UsageError("--frame " + std::to_string(*flags.frame) + ": " + e.what());
    }
  }
  if (!of_diff && (!flags.thresholds.empty() || flags.tolerance))
    throw UsageError("--thresholds and --tolerance apply to the report of a diff: give two captures");
  // With a golden, the golden is A and the one capture given is B. Everything is opened before an
  // earlier report is replaced.
  const std::optional<nc::Capture> capture_b =
      of_diff ? std::optional(nc::Capture::open(flags.golden ? a : b)) : std::nullopt;
  nc::Thresholds thresholds;
  const nc::DiffOptions options = diff_options(flags, thresholds);
  prepare_report_folder(output, force);
  try {
    if (capture_b)
      nc::write_diff_report(capture, *capture_b, options, output);
    else
      nc::write_capture_report(capture, output, {.frame = flags.frame});
  } catch (...) {
    // The folder was empty: what is in it is this run's, and a report cut short leaves nothing.
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator(output, ignored))
      std::filesystem::remove_all(entry.path(), ignored);
    throw;
  }
  std::cout << "report: " << (std::filesystem::path(output) / "index.html").string() << "\n";
  return 0;
}

// Interactive without -c or --script. Scripted, every command runs (a failed one does not stop
// the others) and the exit code says whether any failed.
int run_inspect(const std::string& path, const std::string& commands, const std::string& script_file,
                const std::string& device) {
  nc::InspectSession session(nc::Capture::open(path), {device, validation_requested()});
  nc::InspectCommands runner(session, std::cout, std::cerr);
  if (commands.empty() && script_file.empty()) {
    nc::run_interactive_inspect(session, runner);
    return 0;
  }
  std::string script = commands;
  if (!script_file.empty()) {
    std::ifstream file(script_file, std::ios::binary);
    if (!file) throw UsageError("--script " + script_file + ": cannot read");
    std::ostringstream text;
    text << file.rdbuf();
    script = text.str();
  }
  bool failed = false;
  for (const std::string& command : nc::split_commands(script)) {
    failed |= !runner.run(command);
    if (runner.finished()) break;
  }
  return failed ? kExitBadInput : 0;
}

std::string inspect_commands_help() {
  std::string text = "Commands (every one takes --json; `help CMD` inside a session):\n";
  for (const nc::InspectCommandHelp& c : nc::inspect_commands()) text += "  " + c.usage + "\n      " + c.summary + "\n";
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  // The commands load image blobs of several MB one after another. By default glibc maps each
  // such buffer on its own and unmaps it when freed, so every load faults its pages in anew (a
  // quarter of a diff's time); kept in the heap, freed buffers are reused.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{
      "nightcap: render-capture analysis and replay.\n"
      "Exit codes: 0 success, 1 differences beyond tolerance, 2 bad input or failure."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every command");

  RenderFlags r;
  std::vector<std::string> sets, shaders, pass_names;
  std::string device;
  bool json = false, verify = false, chain = false;
  auto* render = app.add_subcommand("render", "Render a scene (glTF, or the built-in map) to a capture");
  render->add_option("scene", r.scene_path,
                     "glTF 2.0 file (.gltf/.glb); omitted: the built-in 16 km map from its street shot");
  render->add_option("-o,--output", r.out, "capture folder to create")->required();
  render->add_option("--size", r.size, "output size WIDTHxHEIGHT")->capture_default_str();
  render->add_option("--frames", r.frames, "number of frames to render (1/60 s apart)")->capture_default_str();
  render->add_option("--motion", r.motion, "camera motion along the view: static, walk (1.4 m/s) or drive (14 m/s)")
      ->capture_default_str();
  render->add_option("--cut-at", r.cuts, "frame K cuts to another view; every history restarts (repeatable)");
  render->add_option("--record-frames", r.record,
                     "record only frames A..B (inclusive); the frames before still render so history carries");
  render->add_option("--scene-seed", r.seed, "seed of the built-in map or city block")->capture_default_str();
  auto* shot = render->add_option("--shot", r.shot,
                                  "view of the built-in map: street (the default: 1.7 m up a street), rooftop (60 m "
                                  "up, toward the skyline) or aerial (800 m up at 45°), placed from the seed");
  auto* map_size =
      render->add_option("--map-size", r.map_size, "side of the built-in map in km (0.5 to 16; default 16)");
  render
      ->add_flag("--city-block", r.city_block,
                 "render the built-in one-block city instead of the map (1 022 triangles, 38 lights: small and "
                 "fast, the scene of most tests)")
      ->excludes(shot, map_size);
  render->add_option("--device", r.device, "Vulkan device name (substring); default: lavapipe (llvmpipe)");
  render->add_option("--set", r.sets, "PASS.PARAM=VALUE parameter override (repeatable)");
  auto* hour = render->add_option(
      "--hour", r.hour,
      "time of day, 0 to 24: the scene's sun (or, at night, the full moon) for an equinox at 37.8° N replaces its "
      "first directional light");
  render
      ->add_option("--tod", r.tod,
                   "time-of-day table of `bake-tod` for this map: casters hidden from the light around --hour cast "
                   "no shadow")
      ->needs(hour);
  render->add_option("--orbit", r.orbit, "orbit camera THETA,PHI,RADIUS (degrees, scene units)");
  render->add_option("--target", r.target, "orbit target X,Y,Z (default 0,0,0)");
  render->add_option("--fov", r.fov, "vertical field of view of the orbit camera, degrees")->capture_default_str();
  render
      ->add_option("--codec", r.codec,
                   "OpenEXR compression of every image blob: none, rle, zips, zip, piz or pxr24 (zip1 … zip9: "
                   "with a zlib level); auto: ZIP at zlib level 1, nightcap's own writer")
      ->capture_default_str();
  render->add_option("--inject-nan", r.inject_nan,
                     "PASS:X,Y: after PASS runs, write a NaN into its first float output at output pixel (X, Y), "
                     "to test `inspect` (nan) and the passes after it (repeatable, one per pass)");
  render->add_flag("--force", r.force, "replace an existing capture");

  uint32_t bake_seed = 1;
  double bake_size = 16.0;
  std::string bake_out;
  auto* bake_tod = app.add_subcommand(
      "bake-tod",
      "Bake which casters of the built-in map can cast a visible shadow at each of 12 hours (every 2 h): each 256 m "
      "sector and its 8 neighbours rasterised from the sun or moon; `render --hour H --tod FILE` reads it");
  bake_tod->add_option("--scene-seed", bake_seed, "seed of the built-in map")->capture_default_str();
  bake_tod->add_option("--map-size", bake_size, "side of the built-in map in km (0.5 to 16)")->capture_default_str();
  bake_tod->add_option("-o,--output", bake_out, "table file to write (replaced atomically)")->required();

  std::string capture_path, capture_b;
  auto* passes = app.add_subcommand("passes", "List the passes of a capture");
  passes->add_option("capture", capture_path, "capture folder")->required();
  passes->add_flag("--json", json, "machine-readable output");

  auto* check = app.add_subcommand(
      "check",
      "Read every blob of a capture, decode it and check its content hash (other commands read only the blobs they "
      "need): name each bad blob, what is wrong (missing, refused, truncated, undecodable, hash_mismatch) and the "
      "records that refer to it.\nExit codes: 0 every blob is sound, 2 a bad blob or an unreadable manifest.");
  check->add_option("capture", capture_path, "capture folder")->required();
  check->add_flag("--json", json, "machine-readable output");

  uint32_t frame = 0;
  auto* replay = app.add_subcommand("replay", "Re-execute passes of a capture from their recorded inputs");
  replay->add_option("capture", capture_path, "capture folder")->required();
  replay->add_option("--frame", frame, "frame index")->capture_default_str();
  replay->add_option("--pass", pass_names, "pass to replay (repeatable; default: every pass that ran)");
  replay->add_option("--set", sets, "PASS.PARAM=VALUE parameter override (repeatable)");
  replay->add_option("--shader", shaders, "PASS=FILE: replace the pass's shader of FILE's stage (.vert/.frag/.comp)");
  replay->add_option("--device", device, "Vulkan device name (substring); default: lavapipe");
  replay->add_flag("--verify", verify, "compare every output with the recorded one (exit 1 if any differs)");
  replay->add_flag("--chain", chain, "feed replayed outputs to later passes instead of the recorded inputs");
  replay->add_flag("--json", json, "machine-readable output");

  double tolerance = 0.0;
  uint32_t diff_frame = 0;
  auto* diff = app.add_subcommand(
      "diff",
      "Compare two captures pass by pass and name the first divergent pass: `diff CAP_A CAP_B`, or a capture with a "
      "golden of a store, the reference: `diff --golden NAME --store DIR CAP`.\n"
      "Exit codes: 0 every result within what it was held to, 1 a regression, 2 an error (a missing golden too).");
  auto* capture_a_option =
      diff->add_option("capture_a", capture_path, "reference capture (with --golden: the capture)");
  auto* capture_b_option = diff->add_option("capture_b", capture_b, "capture to compare");
  DiffFlags diff_flags;
  std::string diff_golden;
  auto* golden_option =
      diff->add_option("--golden", diff_golden, "compare the capture with golden NAME of --store (capture A)");
  auto* store_option = diff->add_option("--store", diff_flags.store, "the golden store (`nightcap golden update`)");
  golden_option->needs(store_option);
  store_option->needs(golden_option);
  diff->add_option("--thresholds", diff_flags.thresholds,
                   "JSON rules (glob on PASS/RESOURCE, metric, limit, allowed share, ignored rectangles) that replace "
                   "the recorded contracts of the outputs they match (format: docs/commands/diff.md)");
  auto* tolerance_option = diff->add_option(
      "--tolerance", tolerance,
      "max abs difference accepted for float outputs no --thresholds rule matches, instead of their recorded "
      "contracts (others keep theirs)");
  auto* diff_frame_option = diff->add_option("--frame", diff_frame, "compare frame K only");
  diff->add_option("--junit", diff_flags.junit, "also write JUnit XML: one test case per pass and output");
  diff->add_option("--flip-maps", diff_flags.flip_maps,
                   "write the FLIP error map of each displayed image that differs into DIR as PNG (magma colours)");
  diff->add_flag("--isolate", diff_flags.isolate,
                 "run each differing pass as B recorded it on A's inputs: did the pass change, or its inputs?");
  diff->add_option("--device", diff_flags.device,
                   "Vulkan device of --isolate's runs (name substring); default: lavapipe");
  diff->add_flag("--json", json, "machine-readable output (the last line, the counts, goes to stderr)");

  std::string store_dir, golden_name;
  auto* golden = app.add_subcommand("golden", "Keep golden captures in a store: the references of `diff --golden`");
  golden->require_subcommand(1);
  auto* golden_update = golden->add_subcommand(
      "update",
      "Record a capture as golden NAME of a store, replacing an earlier golden of that name (the store is created "
      "when absent; blobs it holds already are not copied again)");
  golden_update->add_option("capture", capture_path, "capture folder")->required();
  golden_update->add_option("--store", store_dir, "store folder")->required();
  golden_update->add_option("--name", golden_name, "golden name (printable, no spaces, '/' or '\\')")->required();
  auto* golden_list = golden->add_subcommand("list", "List the goldens of a store");
  golden_list->add_option("--store", store_dir, "store folder")->required();
  golden_list->add_flag("--json", json, "machine-readable output");

  std::string graph_output;
  bool dot = false;
  auto* graph = app.add_subcommand("graph", "Draw one frame's render graph: passes and resource versions");
  graph->add_option("capture", capture_path, "capture folder")->required();
  graph->add_option("--frame", frame, "frame index")->capture_default_str();
  // DOT is the only format so far; required so that a later one (--json) can stand beside it.
  graph->add_flag("--dot", dot, "write Graphviz DOT (render it with e.g. `dot -Tsvg`)")->required();
  graph->add_option("-o,--output", graph_output, "file to write (default: standard output)");

  std::string report_output, report_b;
  uint32_t report_frame = 0;
  bool report_force = false;
  DiffFlags report_flags;
  double report_tolerance = 0.0;
  auto* report = app.add_subcommand(
      "report", "Write a capture, or the diff of two, as a static HTML report (opens from disk, no server needed)");
  report->add_option("capture", capture_path, "capture folder (of a diff: the reference, A)")->required();
  report->add_option("capture_b", report_b, "the new capture (B): write the report of the diff of A and B");
  report->add_option("-o,--output", report_output, "folder to write (must not exist, or be empty)")->required();
  auto* report_frame_option = report->add_option(
      "--frame", report_frame, "frame to show (default: the first the capture recorded; of a diff: every frame)");
  report->add_flag("--force", report_force, "replace an earlier report in the output folder");
  auto* report_golden = report->add_option("--golden", report_flags.golden,
                                           "the diff of CAPTURE against this golden of --store (the golden is A)");
  report->add_option("--store", report_flags.store, "store of goldens (with --golden)");
  report->add_option("--thresholds", report_flags.thresholds, "of a diff: threshold rules, as `diff --thresholds`");
  auto* report_tolerance_option = report->add_option("--tolerance", report_tolerance,
                                                     "of a diff: max abs for float outputs, as `diff --tolerance`");

  std::string inspect_commands, inspect_script;
  auto* inspect = app.add_subcommand(
      "inspect", "Step through a capture pass by pass: pixels, buffers and statistics decoded by what they hold");
  inspect->add_option("capture", capture_path, "capture folder")->required();
  auto* commands_option =
      inspect->add_option("-c,--commands", inspect_commands, "run these commands (separated by ';') and exit");
  inspect->add_option("--script", inspect_script, "run the commands of FILE (one a line, or separated by ';') and exit")
      ->excludes(commands_option);
  inspect->add_option("--device", device,
                      "Vulkan device for the commands that run a pass again (replay, pick); default: lavapipe");
  inspect->footer(inspect_commands_help() +
                  "Without -c or --script the session is interactive (history, tab completion). Scripted, the exit "
                  "code is 2 if any command failed, else 0.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  }
  int code = kExitBadInput;
  try {
    if (*render) code = run_render(r);
    if (*bake_tod) code = run_bake_tod(bake_seed, bake_size, bake_out);
    if (*passes) code = run_passes(capture_path, json);
    if (*check) code = run_check(capture_path, json);
    if (*replay) code = run_replay(capture_path, frame, pass_names, sets, shaders, device, verify, chain, json);
    if (*diff) {
      if (tolerance_option->count()) diff_flags.tolerance = tolerance;
      if (diff_frame_option->count()) diff_flags.frame = diff_frame;
      diff_flags.json = json;
      // Two captures, or a golden and one capture: never a mixture.
      if (golden_option->count()) {
        diff_flags.golden = diff_golden;
        if (capture_b_option->count())
          throw UsageError("--golden compares one capture with the golden: give one capture, not two");
        if (!capture_a_option->count())
          throw UsageError("--golden NAME --store DIR: the capture to compare is missing");
        code = run_diff("", capture_path, diff_flags);
      } else {
        if (!capture_b_option->count())
          throw UsageError("diff needs two captures (CAP_A CAP_B), or --golden NAME --store DIR and one capture");
        code = run_diff(capture_path, capture_b, diff_flags);
      }
    }
    if (*golden_update) code = run_golden_update(capture_path, store_dir, golden_name);
    if (*golden_list) code = run_golden_list(store_dir, json);
    if (*graph) code = run_graph(capture_path, frame, graph_output);
    if (*report) {
      if (report_frame_option->count()) report_flags.frame = report_frame;
      if (report_tolerance_option->count()) report_flags.tolerance = report_tolerance;
      if (report_golden->count() && !report_b.empty())
        throw UsageError("--golden compares one capture with the golden: give one capture, not two");
      if (report_golden->count() && report_flags.store.empty()) throw UsageError("--golden needs --store DIR");
      code = run_report(capture_path, report_b, report_flags, report_output, report_force);
    }
    if (*inspect) code = run_inspect(capture_path, inspect_commands, inspect_script, device);
  } catch (const std::exception& e) {
    std::cerr << "nightcap: " << e.what() << "\n";
  }
  // Checked here, once every device is destroyed: destruction reports leaked objects too.
  // Validation errors fail the command: tests run with the layer and must see none.
  if (const uint32_t errors = nc::validation_errors_reported(); errors > 0) {
    std::cerr << "nightcap: " << errors << " Vulkan validation error(s) reported\n";
    return kExitBadInput;
  }
  return code;
}
