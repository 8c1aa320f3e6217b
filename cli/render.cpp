// `render` (a scene to a capture, frame by frame, stopped cleanly by SIGINT or SIGTERM) and
// `bake-tod` (the built-in map's time-of-day table).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/command.h"
#include "passes/assembly/renderer.h"
#include "passes/assembly/supersample.h"
#include "passes/scene/time_of_day.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

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

struct RenderFlags {
  std::string scene_path, out, size = "1280x720", device, orbit, target, codec = "auto", motion = "walk", record, shot,
                               pass_times = "auto";
  uint32_t frames = 1, seed = 1, supersample = 0;
  double map_size = 0.0;  // 0: not given
  double fov = 45.0;
  std::optional<double> hour;
  std::string tod;
  std::vector<std::string> sets, inject_nan;
  std::vector<uint32_t> cuts;
  bool force = false, city_block = false, freeze = false;
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
  if (flags.pass_times != "auto") {
    settings.pass_timing = nc::pass_timing_from_name(flags.pass_times);
    if (!settings.pass_timing)
      throw UsageError("--pass-times '" + flags.pass_times + "': expected auto, alone or overlapped");
  }
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
  if (flags.freeze) scene = nc::frozen(std::move(scene));
  if (flags.supersample &&
      (!flags.freeze || settings.path.motion != nc::CameraPath::Motion::still || !flags.cuts.empty()))
    throw UsageError("--supersample " + std::to_string(flags.supersample) +
                     " averages renders of one still frame: give it with --motion static and --freeze, without "
                     "--cut-at (and render the capture to compare with so too)");
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
                          {"inject_nan", flags.inject_nan},
                          {"pass_times", flags.pass_times}};
  if (flags.hour) settings.description["hour"] = *flags.hour;
  if (flags.freeze) settings.description["freeze"] = true;
  if (flags.supersample) settings.description["supersample"] = flags.supersample;
  if (!flags.tod.empty()) settings.description["tod"] = flags.tod;
  nc::GpuDevice gpu({flags.device, validation_requested()});
  stop_on_signals();
  nc::RenderSummary summary;
  if (flags.supersample) {
    const uint32_t n = flags.supersample;
    // taa.supersampled reads nothing: asking for lighting.lit keeps the passes before it running and
    // recorded, as in the TAA capture it is compared with.
    settings.sinks = nc::frame_sinks();
    settings.sinks.push_back("lighting.lit");
    const std::vector<double> lit = nc::supersampled_lit(gpu, scene, settings, n, render_monitor());
    summary = nc::render_to_capture(gpu, scene, settings, nc::supersampled_frame_passes(lit, n * n), flags.out,
                                    flags.force, render_monitor());
  } else {
    summary = nc::render_to_capture(gpu, scene, settings, flags.out, flags.force, render_monitor());
  }
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

}  // namespace

Command add_render_command(CLI::App& app) {
  auto flags = std::make_shared<RenderFlags>();
  RenderFlags& r = *flags;
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
  render
      ->add_option("--pass-times", r.pass_times,
                   "how pass times are measured: alone (each GPU pass submitted by itself, timed by the host's "
                   "clock; encoding waits for the frame), overlapped (the device's timestamps, the frame as a whole) "
                   "or auto (alone on a CPU device such as lavapipe, overlapped on a GPU)")
      ->capture_default_str();
  render->add_flag("--freeze", r.freeze,
                   "cars and pedestrians stand still, drawn as static geometry (a still frame for --supersample)");
  render
      ->add_option("--supersample", r.supersample,
                   "N: the reference TAA is measured against: taa.supersampled writes, in place of taa, the lit colour "
                   "averaged over N² renders of the frame offset across the pixel, TAA off (needs --motion static "
                   "--freeze)")
      ->check(CLI::Range(1, 16));
  render->add_flag("--force", r.force, "replace an existing capture");
  return {render, [flags] { return run_render(*flags); }};
}

Command add_bake_tod_command(CLI::App& app) {
  struct BakeFlags {
    uint32_t seed = 1;
    double size_km = 16.0;
    std::string out;
  };
  auto flags = std::make_shared<BakeFlags>();
  auto* bake_tod = app.add_subcommand(
      "bake-tod",
      "Bake which casters of the built-in map can cast a visible shadow at each of 12 hours (every 2 h): each 256 m "
      "sector and its 8 neighbours rasterised from the sun or moon; `render --hour H --tod FILE` reads it");
  bake_tod->add_option("--scene-seed", flags->seed, "seed of the built-in map")->capture_default_str();
  bake_tod->add_option("--map-size", flags->size_km, "side of the built-in map in km (0.5 to 16)")
      ->capture_default_str();
  bake_tod->add_option("-o,--output", flags->out, "table file to write (replaced atomically)")->required();
  return {bake_tod, [flags] { return run_bake_tod(flags->seed, flags->size_km, flags->out); }};
}
}  // namespace nightcap::cli
