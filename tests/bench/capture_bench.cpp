// What capturing costs: a frame with capture on against off, encoding by codec and workers, bytes per extra frame.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "captures/blob_codec.h"
#include "captures/capture.h"
#include "passes/assembly/renderer.h"
#include "passes/scene/scene.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"

namespace nc = nightcap;
namespace fs = std::filesystem;

namespace nightcap::bench {

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

}  // namespace nightcap::bench
