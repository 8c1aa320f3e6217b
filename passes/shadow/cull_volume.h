// shadow.cull's culling volumes, camera-relative: a plane, a convex volume of them, a slice of the
// view by its corners, and that slice extruded toward the sun (passes/shadow/cull.cpp says why a
// caster outside it is dropped).
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <vector>

namespace nightcap::shadow_cull {

using glm::dvec3;

struct Plane {
  dvec3 normal;   // inward
  double offset;  // inside where dot(normal, p) + offset ≥ 0
  double distance(const dvec3& p) const { return glm::dot(normal, p) + offset; }
};

struct Volume {
  std::vector<Plane> planes;
  // Outside when the box lies wholly outside one plane.
  bool excludes(const dvec3& lo, const dvec3& hi) const {
    for (const Plane& p : planes) {
      const dvec3 far_corner(p.normal.x >= 0 ? hi.x : lo.x, p.normal.y >= 0 ? hi.y : lo.y,
                             p.normal.z >= 0 ? hi.z : lo.z);
      if (p.distance(far_corner) < 0.0) return true;
    }
    return false;
  }
};

// Corner k of a slice: bit 0 right, bit 1 top, bit 2 far.
using Corners = std::array<dvec3, 8>;

// The slice extruded toward the sun (`to_sun`, unit), every plane moved out by `margin` metres
// and, along the sun's rays, by `depth_margin` more: the resolve carries a receiver's depth along
// its plane to texels up to `margin` away, so a caster that much deeper than it can still count.
Volume extruded_slice(const Corners& c, const dvec3& to_sun, double margin, double depth_margin);

}  // namespace nightcap::shadow_cull
