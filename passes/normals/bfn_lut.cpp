#include "passes/normals/bfn_lut.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <thread>

namespace nightcap {

uint8_t encode_unorm8(float signed_value) {
  return static_cast<uint8_t>(std::lround(std::clamp(signed_value * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f));
}

float decode_signed8(uint8_t code) { return code * (2.0f / 255.0f) - 1.0f; }

std::vector<uint8_t> build_bfn_lut(uint32_t size) {
  std::vector<uint8_t> table(size_t(size) * size);
  auto fill_rows = [&](uint32_t first, uint32_t step) {
    // The shader indexes with u ≥ v (column ≥ row); the other triangle mirrors it.
    for (uint32_t row = first; row < size; row += step)
      for (uint32_t column = row; column < size; ++column) {
        const double u = double(column) / (size - 1), v = double(row) / (size - 1);
        const double length = std::sqrt(1.0 + u * u + v * v);
        const double dx = 1.0 / length, dy = u / length, dz = v / length;
        double best_cosine = -2.0;
        int best_major = 255;
        // Major codes 128..255 decode to lengths (0, 1]; the minors follow by rounding.
        for (int major = 128; major <= 255; ++major) {
          const float t = decode_signed8(uint8_t(major));
          const double x = decode_signed8(uint8_t(major));
          const double y = decode_signed8(encode_unorm8(float(u) * t));
          const double z = decode_signed8(encode_unorm8(float(v) * t));
          const double cosine = (x * dx + y * dy + z * dz) / std::sqrt(x * x + y * y + z * z);
          if (cosine > best_cosine) {
            best_cosine = cosine;
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

}  // namespace nightcap
