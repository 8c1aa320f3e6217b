// A CPU reference for depth.convert's half-resolution outputs, shared by the unit test and the
// benchmark, written from the rule the pass documents: each half texel covers the 2×2 footprint
// of full texels (2x, 2y)…(2x + 1, 2y + 1), cut at the image's edge for odd sizes; it takes its
// depth and its stencil from the footprint's texel nearest the camera (the largest reversed-Z
// device depth, the first in row order among equals); the depth is znear / device in metres in
// double precision, sky_depth where device is 0, at most sky_depth, and then at most 65504 (the
// largest finite half).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace nightcap::reference {

struct HalfDepthStencil {
  uint32_t width = 0, height = 0;
  std::vector<size_t> source;  // the full-resolution texel each half texel takes
  std::vector<double> metres;  // exact, then clamped at 65504
  std::vector<uint8_t> stencil;
};

inline HalfDepthStencil half_depth_stencil(const std::vector<float>& device, const std::vector<uint8_t>& stencil,
                                           uint32_t width, uint32_t height, double znear, double sky_depth) {
  HalfDepthStencil half;
  half.width = (width + 1) / 2;
  half.height = (height + 1) / 2;
  for (uint32_t y = 0; y < half.height; ++y)
    for (uint32_t x = 0; x < half.width; ++x) {
      size_t best = size_t(2 * y) * width + 2 * x;
      for (uint32_t fy = 2 * y; fy < std::min(2 * y + 2, height); ++fy)
        for (uint32_t fx = 2 * x; fx < std::min(2 * x + 2, width); ++fx) {
          const size_t i = size_t(fy) * width + fx;
          if (device[i] > device[best]) best = i;
        }
      const double d = device[best];
      const double metres = d > 0 ? std::min(znear / d, sky_depth) : sky_depth;
      half.source.push_back(best);
      half.metres.push_back(std::min(metres, 65504.0));
      half.stencil.push_back(stencil[best]);
    }
  return half;
}

}  // namespace nightcap::reference
