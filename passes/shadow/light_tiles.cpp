#include "passes/shadow/light_tiles.h"

#include <algorithm>

namespace nightcap {

LightAxes LightAxes::of_sun(const glm::dvec3& travel) {
  const glm::dvec3 helper = std::abs(travel.y) < 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  LightAxes axes;
  axes.travel = travel;
  axes.x = glm::normalize(glm::cross(helper, travel));
  axes.y = glm::cross(travel, axes.x);
  return axes;
}

LightRect across_sun(const LightAxes& axes, const glm::dvec3& lo, const glm::dvec3& hi) {
  LightRect r;
  for (int k = 0; k < 8; ++k)
    r.grow(axes.across(glm::dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z)));
  return r;
}

LightRect across_sun(const LightAxes& axes, const glm::dmat4& model, const MeshRecord& mesh) {
  LightRect r;
  for (int k = 0; k < 8; ++k)
    r.grow(axes.across(glm::dvec3(model * glm::dvec4(k & 1 ? mesh.bounds_max[0] : mesh.bounds_min[0],
                                                     k & 2 ? mesh.bounds_max[1] : mesh.bounds_min[1],
                                                     k & 4 ? mesh.bounds_max[2] : mesh.bounds_min[2], 1.0))));
  return r;
}

uint64_t TiledMap::meeting(const LightRect& r) const {
  const double side = texel * (resolution / tiles);
  const glm::dvec2 lo = glm::floor((r.lo - origin + texel) / side), hi = glm::floor((r.hi - origin - texel) / side);
  // The tile rectangles overlap by a texel: widen the range by one and let tile() decide.
  uint64_t mask = 0;
  for (double y = std::max(0.0, lo.y - 1); y <= std::min(double(tiles) - 1, hi.y + 1); ++y)
    for (double x = std::max(0.0, lo.x - 1); x <= std::min(double(tiles) - 1, hi.x + 1); ++x) {
      const uint32_t t = uint32_t(y) * tiles + uint32_t(x);
      if (tile(t).meets(r)) mask |= uint64_t(1) << t;
    }
  return mask;
}

TilesAfterMove tiles_after_move(uint64_t complete_before, glm::ivec2 shift, uint32_t tiles, uint32_t resolution) {
  const int side = int(resolution / tiles), n = int(resolution);
  TilesAfterMove after;
  for (uint32_t ty = 0; ty < tiles; ++ty)
    for (uint32_t tx = 0; tx < tiles; ++tx) {
      const uint64_t bit = uint64_t(1) << (ty * tiles + tx);
      // The previous frame's texels under this tile: [lo, hi] on each axis, then the part inside the map.
      const glm::ivec2 lo = glm::ivec2(int(tx), int(ty)) * side + shift, hi = lo + side - 1;
      const glm::ivec2 in_lo = glm::max(lo, glm::ivec2(0)), in_hi = glm::min(hi, glm::ivec2(n - 1));
      if (in_lo != lo || in_hi != hi) after.uncovered |= bit;
      if (glm::any(glm::greaterThan(in_lo, in_hi))) continue;
      for (int y = in_lo.y / side; y <= in_hi.y / side; ++y)
        for (int x = in_lo.x / side; x <= in_hi.x / side; ++x)
          if (!(complete_before >> (y * int(tiles) + x) & 1u)) after.stale |= bit;
    }
  return after;
}

UncoveredStrips uncovered_strips(uint32_t resolution, glm::ivec2 shift) {
  const int32_t n = int32_t(resolution);
  // This frame's texels i with i + s outside [0, n): [0, -s) or [n - s, n), clamped to the map.
  auto outside = [n](int32_t s) { return s < 0 ? std::pair{0, std::min(n, -s)} : std::pair{std::max(0, n - s), n}; };
  const auto [x0, x1] = outside(shift.x);
  const auto [y0, y1] = outside(shift.y);
  UncoveredStrips strips;
  if (x0 < x1) strips.columns = {x0, 0, x1, n};
  // The rows' texels outside the columns: the columns lie at one side, so the rest is one range.
  const int32_t rest0 = x0 < x1 && x0 == 0 ? x1 : 0, rest1 = x0 < x1 && x1 == n ? x0 : n;
  if (y0 < y1 && rest0 < rest1) strips.rows = {rest0, y0, rest1, y1};
  return strips;
}

}  // namespace nightcap
