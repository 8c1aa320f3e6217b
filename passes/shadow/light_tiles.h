// The sun's shadow maps seen as tiles in light space: what shadow.cull (the cascades' static
// layers) and shadow.distant_plan (the distant levels) share to keep a map that moves with the
// camera by whole texels and to redraw only the tiles whose depth is missing, a few a frame.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "passes/frame/hierarchy.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

// Axes across the sun's rays and along them (`travel`, the way sunlight goes): any basis around
// the sun, the same one for a given sun in every pass.
struct LightAxes {
  glm::dvec3 x{0.0}, y{0.0}, travel{0.0};
  static LightAxes of_sun(const glm::dvec3& travel);
  glm::dvec2 across(const glm::dvec3& p) const { return {glm::dot(p, x), glm::dot(p, y)}; }
};

// A rectangle across the sun, in world light-space metres.
struct LightRect {
  glm::dvec2 lo{INFINITY}, hi{-INFINITY};
  bool meets(const LightRect& o) const { return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y; }
  void grow(const glm::dvec2& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
};

// The rectangle a world box covers across the sun.
LightRect across_sun(const LightAxes& axes, const glm::dvec3& lo, const glm::dvec3& hi);
// The rectangle a mesh's box under `model` covers across the sun (its 8 corners, not the world
// box around them).
LightRect across_sun(const LightAxes& axes, const glm::dmat4& model, const MeshRecord& mesh);

// Texels [x0, x1) × [y0, y1) of a map.
struct MapTexels {
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
};

// A square map of `resolution` texels per side cut into `tiles`² tiles (bit ty·tiles + tx of a
// mask), whose texel (0, 0) has its corner at `origin` (world light-space metres).
struct TiledMap {
  glm::dvec2 origin{0.0};
  double texel = 0.0;
  uint32_t resolution = 0, tiles = 1;
  uint64_t all() const { return tiles * tiles == 64 ? ~uint64_t(0) : (uint64_t(1) << (tiles * tiles)) - 1; }
  MapTexels tile_texels(uint32_t t) const {
    const int32_t side = int32_t(resolution / tiles);
    const int32_t x = int32_t(t % tiles) * side, y = int32_t(t / tiles) * side;
    return {x, y, x + side, y + side};
  }
  // Texels' rectangle grown by a texel each side: a caster whose box meets it may cover one of them.
  LightRect texels(const MapTexels& r) const {
    return {origin + glm::dvec2(r.x0 - 1, r.y0 - 1) * texel, origin + glm::dvec2(r.x1 + 1, r.y1 + 1) * texel};
  }
  LightRect tile(uint32_t t) const { return texels(tile_texels(t)); }
  // The whole map's rectangle, grown by a texel each side.
  LightRect whole() const { return {origin - texel, origin + texel * (resolution + 1.0)}; }
  // The tiles a rectangle meets.
  uint64_t meeting(const LightRect& r) const;
};

// The tiles of a map that moved by `shift` texels (this frame's texel t covers the previous
// frame's t + shift): `stale`, some texel of theirs lay in a tile of the previous map that was
// not complete; `uncovered`, some texel of theirs lay outside the previous map.
struct TilesAfterMove {
  uint64_t stale = 0, uncovered = 0;
};
TilesAfterMove tiles_after_move(uint64_t complete_before, glm::ivec2 shift, uint32_t tiles, uint32_t resolution);

// The texels of a map moved by `shift` that lay outside the previous map: the columns (full
// height), and the rows (without those columns, so the two do not overlap).
struct UncoveredStrips {
  MapTexels columns, rows;
};
UncoveredStrips uncovered_strips(uint32_t resolution, glm::ivec2 shift);

// Every static instance in a leaf of the hierarchy whose box, across the sun, meets one of
// `rects`: visit(instance) (the visitor tests the instance's own box).
template <typename Visit>
void visit_static_across_sun(const Hierarchy& hierarchy, const LightAxes& axes, std::span<const LightRect> rects,
                             Visit visit) {
  std::vector<uint32_t> stack;
  if (!hierarchy.static_order.empty() && !rects.empty()) stack.push_back(0);
  while (!stack.empty()) {
    const HierarchyNode& node = hierarchy.nodes[stack.back()];
    stack.pop_back();
    const LightRect r = across_sun(axes, glm::dvec3(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]),
                                   glm::dvec3(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]));
    bool meets = false;
    for (const LightRect& t : rects) meets = meets || r.meets(t);
    if (!meets) continue;
    if (node.count == 0) {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
      continue;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k) visit(hierarchy.static_order[k]);
  }
}

}  // namespace nightcap
