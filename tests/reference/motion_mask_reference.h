// A CPU reference for motion.stencil, shared by the unit test and the benchmark, written from
// what the pass documents: a pixel is tagged when its stencil carries the moving flag or its
// class (the stencil without the moving, road and vehicle marks) is hair or foliage; the mask is
// 1 where any tagged pixel lies within `radius` in both x and y (a square window), 0 elsewhere.
// The dilation is the brute-force window scan.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "passes/scene/scene.h"

namespace nightcap::reference {

inline bool motion_tagged(uint8_t tag) {
  const uint8_t tag_class = tag & uint8_t(~(stencil::moving | stencil::road | stencil::vehicle));
  return (tag & stencil::moving) != 0 || tag_class == stencil::hair || tag_class == stencil::foliage;
}

inline std::vector<uint8_t> motion_mask(const std::vector<uint8_t>& tags, uint32_t width, uint32_t height, int radius) {
  std::vector<uint8_t> mask(tags.size(), 0);
  for (int y = 0; y < int(height); ++y)
    for (int x = 0; x < int(width); ++x)
      for (int sy = std::max(0, y - radius); sy <= std::min(int(height) - 1, y + radius); ++sy)
        for (int sx = std::max(0, x - radius); sx <= std::min(int(width) - 1, x + radius); ++sx)
          if (motion_tagged(tags[size_t(sy) * width + sx])) mask[size_t(y) * width + x] = 1;
  return mask;
}

}  // namespace nightcap::reference
