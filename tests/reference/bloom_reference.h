// A CPU double-precision reference for bloom's levels, shared by its test and the benchmark,
// written from the filter the pass documents rather than from its shader: a level is the 2×2
// box average of the level above (indices clamped into it, so an odd source repeats its last
// row and column), blurred by a Gaussian of σ texels truncated at R = min(8, ⌈3σ⌉) and
// normalised over −R…R, applied along x then y with the level's edge texels repeated outside
// it. A source texel with a NaN channel is black; channels are clamped to [0, 65504].
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "passes/core/format.h"

namespace nightcap::reference {

struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<std::array<double, 3>> texels;  // row-major
  const std::array<double, 3>& at(int64_t x, int64_t y) const {
    x = std::clamp<int64_t>(x, 0, width - 1);
    y = std::clamp<int64_t>(y, 0, height - 1);
    return texels[size_t(y) * width + size_t(x)];
  }
};

// Mip `mip` (layer 0) of an RGBA16F image in nightcap's raw layout, as doubles.
inline RgbImage decode_rgba16f(const std::vector<uint8_t>& raw, const ImageExtent& extent, uint32_t mip) {
  const FormatInfo f = *format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  RgbImage image{mip_size(extent.width, mip), mip_size(extent.height, mip), {}};
  const uint8_t* base = raw.data() + raw_subresource_offset(f, extent, 0, mip, 0);
  image.texels.resize(size_t(image.width) * image.height);
  for (size_t i = 0; i < image.texels.size(); ++i) {
    uint16_t h[4];
    std::memcpy(h, base + 8 * i, 8);
    for (int c = 0; c < 3; ++c) image.texels[i][c] = half_to_float(h[c]);
  }
  return image;
}

inline std::vector<double> gaussian_weights(double sigma) {  // index k: offsets ±k
  const int radius = std::min(8, int(std::ceil(3.0 * sigma)));
  std::vector<double> w(radius + 1);
  double total = 0;
  for (int k = 0; k <= radius; ++k) {
    w[k] = std::exp(-double(k) * k / (2.0 * sigma * sigma));
    total += (k ? 2.0 : 1.0) * w[k];
  }
  for (double& v : w) v /= total;
  return w;
}

// The level of size width×height made from `source` (the level above, or lighting.lit).
inline RgbImage bloom_level(const RgbImage& source, uint32_t width, uint32_t height, double sigma) {
  auto radiance = [&](int64_t x, int64_t y) {
    std::array<double, 3> c = source.at(x, y);
    if (std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2])) return std::array<double, 3>{0, 0, 0};
    for (double& v : c) v = std::clamp(v, 0.0, 65504.0);
    return c;
  };
  RgbImage box{width, height, std::vector<std::array<double, 3>>(size_t(width) * height)};
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        box.texels[size_t(y) * width + x][c] =
            0.25 * (radiance(2 * x, 2 * y)[c] + radiance(2 * x + 1, 2 * y)[c] + radiance(2 * x, 2 * y + 1)[c] +
                    radiance(2 * x + 1, 2 * y + 1)[c]);
  const std::vector<double> w = gaussian_weights(sigma);
  const int radius = int(w.size()) - 1;
  RgbImage rows = box, result = box;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = -radius; k <= radius; ++k) sum += w[std::abs(k)] * box.at(int64_t(x) + k, y)[c];
        rows.texels[size_t(y) * width + x][c] = sum;
      }
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = -radius; k <= radius; ++k) sum += w[std::abs(k)] * rows.at(x, int64_t(y) + k)[c];
        result.texels[size_t(y) * width + x][c] = sum;
      }
  return result;
}

}  // namespace nightcap::reference
