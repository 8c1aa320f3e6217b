// What every stress test checks of the frames it renders: each renders into a capture whose every
// float output of every frame stays finite, and whose named passes replay from their records bit
// for bit (`replay --verify`), every frame.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/frame/scene_resources.h"
#include "replay/replay.h"

namespace nightcap::test {

inline bool all_finite(const ResourceRecord& record, const std::vector<uint8_t>& raw) {
  const FormatInfo f = *format_info(record.format);
  const uint64_t texels = raw_subresource_offset(f, record.extent, 1, 0, 0) / f.texel_bytes;
  for (uint64_t i = 0; i < texels; ++i) {
    float t[4];
    decode_texel(f, 0, raw, i, t);
    for (uint32_t c = 0; c < f.channels; ++c)
      if (!std::isfinite(t[c])) return false;
  }
  return true;
}

// Renders `frames` of `scene` into a capture at `folder`, checks it (above) and returns it open.
inline Capture render_verified(GpuDevice& gpu, const Scene& scene, RenderSettings settings, uint32_t frames,
                               const std::vector<std::string>& passes, const std::filesystem::path& folder) {
  settings.frames = frames;
  render_to_capture(gpu, scene, settings, folder, false);
  Capture capture = Capture::open(folder);
  for (uint32_t f = 0; f < frames; ++f) {
    const FrameRecord& frame = capture.frame(f);
    for (const PassRecord& pass : frame.passes)
      for (const ResourceRecord& out : pass.outputs) {
        if (out.is_buffer || !is_float(*format_info(out.format))) continue;
        EXPECT_TRUE(all_finite(out, capture.load(out)))
            << "frame " << f << ": " << pass.name << " wrote a NaN or Inf to " << out.resource;
      }
    ReplayOptions options;
    options.frame = f;
    options.passes = passes;
    const ReplayReport report = replay_capture(gpu, capture, options);
    for (const PassReplay& pass : report.passes)
      for (const OutputCheck& check : pass.outputs)
        EXPECT_EQ(check.verdict, Verdict::identical) << "frame " << f << ": " << pass.name << " " << check.resource;
  }
  return capture;
}

// The record `resource` that `pass` wrote on frame `f`, as T (empty if it did not run).
template <typename T>
std::vector<T> recorded(const Capture& capture, uint32_t f, const std::string& pass, const std::string& resource) {
  for (const PassRecord& p : capture.frame(f).passes)
    if (p.name == pass)
      for (const ResourceRecord& out : p.outputs)
        if (out.resource == resource) return host_records<T>(capture.load(out));
  return {};
}

}  // namespace nightcap::test
