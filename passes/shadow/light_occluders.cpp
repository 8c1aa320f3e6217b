// LightOccluders: the occluders' pyramid of maxima, and a box's test against it.
#include "passes/shadow/light_occluders.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "passes/frame/scene_resources.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap::shadow_cull {

LightOccluders::LightOccluders(std::span<const uint8_t> data, std::span<const uint8_t> depth, double slope) {
  if (data.size() != sizeof(GpuDistantLevels)) return;
  const GpuDistantLevels levels = host_records<GpuDistantLevels>(data).at(0);
  resolution_ = uint32_t(levels.light_direction.w);
  if (resolution_ == 0 || depth.size() != size_t(resolution_) * resolution_ * sizeof(float)) {
    resolution_ = 0;
    return;
  }
  light_from_world_ = glm::dmat4(levels.light_from_world[0]);
  margin_ = slope * 2.0 * levels.texel_metres[0] / levels.depth_metres[0] + 1e-6;
  // A pyramid of maxima: mip m's texel holds the largest depth of its 2^m × 2^m texels.
  std::vector<float> level(size_t(resolution_) * resolution_);
  std::memcpy(level.data(), depth.data(), depth.size());
  mips_.push_back(std::move(level));
  for (uint32_t side = resolution_; side > 1; side = (side + 1) / 2) {
    const std::vector<float>& fine = mips_.back();
    const uint32_t half = (side + 1) / 2;
    std::vector<float> coarse(size_t(half) * half);
    for (uint32_t y = 0; y < half; ++y)
      for (uint32_t x = 0; x < half; ++x) {
        float m = 0.0f;
        for (uint32_t dy = 0; dy < 2; ++dy)
          for (uint32_t dx = 0; dx < 2; ++dx)
            m = std::max(m, fine[size_t(std::min(2 * y + dy, side - 1)) * side + std::min(2 * x + dx, side - 1)]);
        coarse[size_t(y) * half + x] = m;
      }
    mips_.push_back(std::move(coarse));
  }
}

bool LightOccluders::hides(const Box& box) const {
  if (resolution_ == 0) return false;
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  double nearest = INFINITY;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec4 clip = light_from_world_ * glm::dvec4(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                                                           k & 4 ? box.max.z : box.min.z, 1.0);
    lo = glm::min(lo, glm::dvec2(clip));
    hi = glm::max(hi, glm::dvec2(clip));
    nearest = std::min(nearest, clip.z);
  }
  const double n = resolution_;
  const double x0 = std::floor((lo.x * 0.5 + 0.5) * n) - 1, x1 = std::floor((hi.x * 0.5 + 0.5) * n) + 1;
  const double y0 = std::floor((lo.y * 0.5 + 0.5) * n) - 1, y1 = std::floor((hi.y * 0.5 + 0.5) * n) + 1;
  if (!(x0 >= 0 && y0 >= 0 && x1 < n && y1 < n)) return false;
  // The mip at which the footprint spans at most 2 × 2 texels, then at most 3 × 3 of them.
  uint32_t mip = 0;
  while (mip + 1 < mips_.size() && (uint32_t(x1 - x0) >> mip) > 1) ++mip;
  while (mip + 1 < mips_.size() && (uint32_t(y1 - y0) >> mip) > 1) ++mip;
  const uint32_t side = (resolution_ + (1u << mip) - 1) >> mip;
  float deepest = 0.0f;
  for (uint32_t y = uint32_t(y0) >> mip; y <= (uint32_t(y1) >> mip); ++y)
    for (uint32_t x = uint32_t(x0) >> mip; x <= (uint32_t(x1) >> mip); ++x)
      deepest = std::max(deepest, mips_[mip][size_t(y) * side + x]);
  return double(deepest) < nearest - margin_;
}

}  // namespace nightcap::shadow_cull
