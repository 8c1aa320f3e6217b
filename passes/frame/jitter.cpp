#include "passes/frame/jitter.h"

#include <cmath>

namespace nightcap {
namespace {

// The radical inverse of `index` in `base`: its digits mirrored about the point.
double radical_inverse(uint32_t index, uint32_t base) {
  double value = 0.0, scale = 1.0 / base;
  for (; index > 0; index /= base, scale /= base) value += (index % base) * scale;
  return value;
}

glm::dvec2 halton(uint32_t index) { return {radical_inverse(index, 2), radical_inverse(index, 3)}; }

// The mean of the points of indices 1..kJitterPeriod, which the offsets are taken from.
glm::dvec2 period_mean() {
  glm::dvec2 sum(0.0);
  for (uint32_t index = 1; index <= kJitterPeriod; ++index) sum += halton(index);
  return sum / double(kJitterPeriod);
}

}  // namespace

glm::dvec2 taa_jitter(uint32_t frame_index) {
  if (frame_index == 0) return glm::dvec2(0.0);
  static const glm::dvec2 mean = period_mean();
  return halton((frame_index - 1) % kJitterPeriod + 1) - mean;
}

glm::dvec2 supersample_offset(uint32_t frame_index, uint32_t n) {
  const uint32_t cell = frame_index % (n * n), column = cell % n, row = cell / n;
  return {(column + (row + 0.5) / n) / n - 0.5, (row + (column + 0.5) / n) / n - 0.5};
}

ParamDecl taa_enabled_param() {
  return ParamDecl::boolean("enabled", true,
                            "0 turns TAA off: the camera is not jittered and taa copies lighting.lit unresolved")
      .shared_by("taa");
}

}  // namespace nightcap
