// normals.bfn_lut (CPU): the best-fit normal table, built in code. It depends on nothing but
// its size, so it is built once per process; the capture records it like any other resource.
// Never skipped (frame.md: normals.pack is never skipped).
#include "passes/normals/bfn_lut.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <thread>

#include "passes/core/context.h"
#include "passes/normals/stage.h"

namespace nightcap {

uint8_t encode_unorm8(float signed_value) {
  return static_cast<uint8_t>(std::lround(std::clamp(signed_value * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f));
}

float decode_signed8(uint8_t code) { return code * (2.0f / 255.0f) - 1.0f; }

std::vector<uint8_t> build_bfn_lut(uint32_t size) {
  std::vector<uint8_t> table(size_t(size) * size);
  double decoded[256];
  for (int c = 0; c < 256; ++c) decoded[c] = decode_signed8(uint8_t(c));
  auto fill_rows = [&](uint32_t first, uint32_t step) {
    // The shader indexes with u ≥ v (column ≥ row); the other triangle mirrors it.
    for (uint32_t row = first; row < size; row += step)
      for (uint32_t column = row; column < size; ++column) {
        const float u = float(column) / float(size - 1), v = float(row) / float(size - 1);
        // The direction (1, u, v) up to scale; candidates are compared by cos², which orders
        // them like the angle (all candidates lie within 90° of the direction).
        const double du = u, dv = v, direction2 = 1.0 + du * du + dv * dv;
        double best = -1.0;
        int best_major = 255;
        for (int major = 128; major <= 255; ++major) {
          const float t = float(decoded[major]);
          // round(x·127.5 + 127.5) for x ≥ 0, as encode_unorm8 does.
          const int cu = std::min(255, int(u * t * 127.5f + 128.0f));
          const int cv = std::min(255, int(v * t * 127.5f + 128.0f));
          const double x = decoded[major], y = decoded[cu], z = decoded[cv];
          const double dot = x + y * du + z * dv;
          const double cos2 = dot * dot / ((x * x + y * y + z * z) * direction2);
          if (cos2 > best) {
            best = cos2;
            best_major = major;
          }
        }
        table[size_t(row) * size + column] = table[size_t(column) * size + row] = static_cast<uint8_t>(best_major);
      }
  };
  const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> workers;
  for (uint32_t t = 0; t < threads; ++t) workers.emplace_back(fill_rows, t, threads);
  for (auto& w : workers) w.join();
  return table;
}

namespace {

constexpr uint32_t kLutSize = 1024;

// The table depends on nothing but its size: built once per process.
const std::vector<uint8_t>& cached_lut(uint32_t size) {
  static std::mutex mutex;
  static std::map<uint32_t, std::vector<uint8_t>> tables;
  std::lock_guard lock(mutex);
  auto it = tables.find(size);
  if (it == tables.end()) it = tables.emplace(size, build_bfn_lut(size)).first;
  return it->second;
}

}  // namespace

PassDecl normals_bfn_lut_pass() {
  ImageDecl lut{VK_FORMAT_R8_UINT, kinds::lookup_table};
  lut.size = {SizeRule::Mode::absolute, kLutSize, kLutSize, ""};
  return PassDecl("normals.bfn_lut", PassType::cpu).write("normals.bfn_lut", Use::host, lut).run([](PassContext& ctx) {
    ctx.output("normals.bfn_lut") = cached_lut(kLutSize);
  });
}

}  // namespace nightcap
