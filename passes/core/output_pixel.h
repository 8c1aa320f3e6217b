// How an image smaller or larger than the frame's output lines up with it along one axis: a
// half-resolution resource, a mip or a fixed-size table takes the texel covering the same place
// of the screen. The renderer places `--inject-nan` pixels by it and inspect reads pixels by it,
// so both name the same texel.
#pragma once

#include <cstdint>

namespace nightcap {

// The texel of an axis `texels` long under output pixel `pixel` of an axis `pixels` long.
inline uint32_t texel_under_pixel(uint32_t pixel, uint32_t pixels, uint32_t texels) {
  return uint32_t(uint64_t(pixel) * texels / pixels);
}

// The first output pixel over `texel`; where texels outnumber pixels and none lands on it, the
// pixel covering its place.
inline uint32_t first_pixel_over_texel(uint32_t texel, uint32_t texels, uint32_t pixels) {
  const uint32_t first = uint32_t((uint64_t(texel) * pixels + texels - 1) / texels);
  if (first < pixels && texel_under_pixel(first, pixels, texels) == texel) return first;
  return uint32_t(uint64_t(texel) * pixels / texels);
}

}  // namespace nightcap
