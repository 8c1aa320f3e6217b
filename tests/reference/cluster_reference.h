// A CPU reference for lights.cluster, shared by the unit test and the benchmark, written from the
// documented math (passes/lights/cluster_layout.h, passes/lights/cluster.comp) in double
// precision, from the pass's own float inputs (frame.constants, frame.lights, depth.pyramid):
//
// - The froxel of tile (x, y) and slice k, for tiles of T pixels and S slices: output pixels
//   [Tx, min(Tx + T, W)) × [Ty, …), linear depth [z_k, z_(k+1)) (z_0 = 0, z_S = ∞) clipped to the
//   tile's [min, max] from the pyramid level whose texel covers T pixels (or its last level),
//   texel min(tile, size − 1).
// - The conservative test: the light's core (point, or tube segment) within r' of the froxel's
//   view-space bounding box, and within r' of the inner side of each of the tile's four side
//   planes, r' = range + 2^-12 · (range + farthest end's distance). It returns the margin: the
//   smallest of r' − distance and the four plane slacks; the light is listed when it is ≥ 0. The
//   segment-to-box distance is found here by sorting the segment's crossings of the box's face
//   planes and minimising each quadratic piece, not by the shader's derivative search.
// - Truly reaches: the exact distance from the core to the froxel's frustum cell (a convex
//   polyhedron: four side planes and two depth planes) is at most the range, unpadded. The
//   distance of a point is that to the nearest face polygon (0 inside); of a segment, the
//   minimum over the segment of that convex function, by golden-section search to 2^-40.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "passes/core/format.h"
#include "passes/frame/gpu_types.h"
#include "passes/lights/cluster_layout.h"
#include "passes/scene/scene.h"

namespace nightcap::reference {

struct ClusterView {
  uint32_t width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  uint32_t tile = kClusterTile, slices = kClusterSlices;  // lights.cluster's tile_size and slices
  glm::dmat3 view{1.0};                                   // frame.view's rotation, floats widened
  double sx = 1, sy = 1;                                  // view-space x and y per metre of depth at NDC ±1
  double znear = 0.1, far = 2000;
  std::vector<std::array<double, 2>> tile_depth;  // per tile (row-major): pyramid min, max
};

inline ClusterView cluster_view(const GpuView& frame, std::span<const uint8_t> pyramid,
                                const ImageExtent& pyramid_extent, double max_distance, uint32_t tile = kClusterTile,
                                uint32_t slices = kClusterSlices) {
  ClusterView v;
  v.tile = tile;
  v.slices = slices;
  v.width = uint32_t(frame.viewport.x);
  v.height = uint32_t(frame.viewport.y);
  v.tiles_x = (v.width + tile - 1) / tile;
  v.tiles_y = (v.height + tile - 1) / tile;
  v.view = glm::dmat3(glm::dmat4(frame.view));
  v.sx = 1.0 / double(frame.projection[0][0]);
  v.sy = -1.0 / double(frame.projection[1][1]);
  v.znear = frame.projection_params.x;
  v.far = std::max(double(float(max_distance)), 2.0 * v.znear);
  // Level 0 is half resolution: level L's texel covers 2^(L+1) output pixels.
  const uint32_t level = std::min<uint32_t>(std::bit_width(tile) - 2, pyramid_extent.mips - 1);
  const FormatInfo format = *format_info(VK_FORMAT_R32G32_SFLOAT);
  const uint64_t base = raw_subresource_offset(format, pyramid_extent, 0, level, 0);
  const uint32_t w = mip_size(pyramid_extent.width, level), h = mip_size(pyramid_extent.height, level);
  for (uint32_t ty = 0; ty < v.tiles_y; ++ty)
    for (uint32_t tx = 0; tx < v.tiles_x; ++tx) {
      float texel[2];
      std::memcpy(texel, pyramid.data() + base + (uint64_t(std::min(ty, h - 1)) * w + std::min(tx, w - 1)) * 8, 8);
      v.tile_depth.push_back({texel[0], texel[1]});
    }
  return v;
}

// Linear depth where slice k starts (k = slices: infinity).
inline double slice_start(const ClusterView& v, uint32_t k) {
  if (k == 0) return 0.0;
  if (k >= v.slices) return std::numeric_limits<double>::infinity();
  return v.znear * std::pow(v.far / v.znear, double(k) / v.slices);
}

struct Froxel {
  bool occupied = false;
  bool marginal = false;               // empty or not by less than the float rounding of its slice bounds
  double near = 0, far = 0;            // clipped linear depth range
  std::array<double, 4> extent{};      // x in [extent[0], extent[2]]·d, y in [extent[1], extent[3]]·d
  glm::dvec3 lo{}, hi{};               // view-space bounding box
  std::array<glm::dvec3, 4> planes{};  // unit inward normals of the side planes (through the camera)
};

// The view-space bounding box of the froxel's extent between its near and far depth.
inline void set_box(Froxel& f) {
  const auto& e = f.extent;
  f.lo = {std::min(e[0] * f.near, e[0] * f.far), std::min(e[1] * f.near, e[1] * f.far), -f.far};
  f.hi = {std::max(e[2] * f.near, e[2] * f.far), std::max(e[3] * f.near, e[3] * f.far), -f.near};
}

inline Froxel froxel(const ClusterView& v, uint32_t tx, uint32_t ty, uint32_t k) {
  Froxel f;
  const auto [tile_min, tile_max] = v.tile_depth[size_t(ty) * v.tiles_x + tx];
  const double start = slice_start(v, k), end = slice_start(v, k + 1);
  f.near = std::max(start, tile_min);
  f.far = std::min(end, tile_max);
  f.occupied = f.near <= f.far;
  // The GPU rounds the slice bounds (exp2 in float); the tile's bounds are its own floats. The
  // froxel is occupied when the slice starts before the tile's far bound and ends after its near
  // one: either comparison within 2^-16 can go both ways.
  f.marginal = std::abs(start - tile_max) <= 0x1p-16 * tile_max || std::abs(end - tile_min) <= 0x1p-16 * tile_min;
  const double x0 = 2.0 * (tx * v.tile) / v.width - 1.0;
  const double x1 = 2.0 * std::min((tx + 1) * v.tile, v.width) / v.width - 1.0;
  const double y0 = 2.0 * (ty * v.tile) / v.height - 1.0;
  const double y1 = 2.0 * std::min((ty + 1) * v.tile, v.height) / v.height - 1.0;
  f.extent = {x0 * v.sx, -y1 * v.sy, x1 * v.sx, -y0 * v.sy};
  set_box(f);
  const auto& e = f.extent;
  f.planes = {glm::normalize(glm::dvec3(1, 0, e[0])), glm::normalize(glm::dvec3(0, 1, e[1])),
              glm::normalize(glm::dvec3(-1, 0, -e[2])), glm::normalize(glm::dvec3(0, -1, -e[3]))};
  return f;
}

// A marginal froxel as the GPU builds it when it finds it occupied, up to rounding: its depth
// range shrunk to the centre of its band (near and far within 2^-16 of the depth). The GPU's
// range lies within 2^-15 · depth of that centre (its slice bound rounded by up to 2^-16 more),
// which moves a light's distance to the box by at most √(1 + ex² + ey²) · 2^-15 · depth: under
// 2^-13 · scale less the GPU's own 2^-16 · scale for views up to 120° (|ex|, |ey| ≤ √3), since a
// light that reaches depth d has range + distance ≥ d.
inline Froxel thin_froxel(const Froxel& marginal) {
  Froxel f = marginal;
  f.occupied = true;
  f.near = f.far = 0.5 * (marginal.near + marginal.far);
  set_box(f);
  return f;
}

// The slice next to marginal froxel k that shares its band: the band is where the tile's surfaces
// meet a slice bound, and the slice on the other side of that bound holds them.
inline uint32_t band_neighbour(const ClusterView& v, const Froxel& marginal, uint32_t k) {
  const double band = 0.5 * (marginal.near + marginal.far);
  const bool at_start =
      k + 1 == v.slices || std::abs(band - slice_start(v, k)) < std::abs(band - slice_start(v, k + 1));
  return at_start ? k - 1 : k + 1;
}

struct LightCore {
  enum class Reach { none, bounded, everywhere } reach = Reach::none;
  glm::dvec3 a{}, b{};  // view space
  double range = 0, padded = 0;
  double scale = 0;  // range + the farthest end's distance: what float rounding is relative to
};

inline LightCore light_core(const ClusterView& v, const GpuLight& light) {
  LightCore c;
  const auto type = LightType(uint32_t(light.position_type.w));
  if (type == LightType::directional) return c;
  c.range = light.color_range.w;
  if (!(c.range > 0)) {
    c.reach = LightCore::Reach::everywhere;
    return c;
  }
  c.reach = LightCore::Reach::bounded;
  c.a = v.view * glm::dvec3(glm::vec3(light.position_type));
  c.b = type == LightType::tube ? v.view * glm::dvec3(glm::vec3(light.end_radius)) : c.a;
  c.scale = c.range + std::max(glm::length(c.a), glm::length(c.b));
  c.padded = c.range + 0x1p-12 * c.scale;
  return c;
}

// Distance from the segment [a, b] to the box [lo, hi].
inline double segment_box_distance(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& lo,
                                   const glm::dvec3& hi) {
  const glm::dvec3 d = b - a;
  auto squared = [&](double t) {
    const glm::dvec3 p = a + t * d;
    const glm::dvec3 e = p - glm::clamp(p, lo, hi);
    return glm::dot(e, e);
  };
  std::vector<double> ts = {0.0, 1.0};
  for (int i = 0; i < 3; ++i)
    if (d[i] != 0)
      for (double bound : {lo[i], hi[i]}) {
        const double t = (bound - a[i]) / d[i];
        if (t > 0 && t < 1) ts.push_back(t);
      }
  std::sort(ts.begin(), ts.end());
  double best = std::min(squared(0.0), squared(1.0));
  for (size_t k = 0; k + 1 < ts.size(); ++k) {
    // Inside the piece each axis is below, within or above the box throughout: a quadratic.
    const glm::dvec3 mid = a + 0.5 * (ts[k] + ts[k + 1]) * d;
    double num = 0, den = 0;
    for (int i = 0; i < 3; ++i) {
      const double bound = mid[i] < lo[i] ? lo[i] : mid[i] > hi[i] ? hi[i] : std::nan("");
      if (std::isnan(bound)) continue;
      num -= (a[i] - bound) * d[i];
      den += d[i] * d[i];
    }
    const double t = den > 0 ? std::clamp(num / den, ts[k], ts[k + 1]) : ts[k];
    best = std::min(best, squared(t));
  }
  return std::sqrt(best);
}

// The conservative test's margin: listed when ≥ 0 (±∞ for lights that reach every occupied
// froxel, or none).
inline double conservative_margin(const Froxel& f, const LightCore& c) {
  if (!f.occupied || c.reach == LightCore::Reach::none) return -std::numeric_limits<double>::infinity();
  if (c.reach == LightCore::Reach::everywhere) return std::numeric_limits<double>::infinity();
  double margin = c.padded - segment_box_distance(c.a, c.b, f.lo, f.hi);
  for (const glm::dvec3& n : f.planes)
    margin = std::min(margin, std::max(glm::dot(n, c.a), glm::dot(n, c.b)) + c.padded);
  return margin;
}

inline double point_segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = b - a;
  const double dd = glm::dot(d, d);
  const double t = dd > 0 ? std::clamp(glm::dot(p - a, d) / dd, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * d));
}

// The froxel's frustum cell: six faces, each a quad (the side faces degenerate to segments when
// near = far), and a bounding sphere for a cheap, exact rejection.
struct FroxelCell {
  std::array<std::array<glm::dvec3, 4>, 6> faces;
  glm::dvec3 centre{0.0};
  double radius = 0;
};

inline FroxelCell froxel_cell(const Froxel& f) {
  const auto& e = f.extent;
  auto vertex = [&](int xi, int yi, double d) { return glm::dvec3(e[xi ? 2 : 0] * d, e[yi ? 3 : 1] * d, -d); };
  FroxelCell cell;
  auto& faces = cell.faces;
  const double depth[2] = {f.near, f.far};
  for (int s = 0; s < 2; ++s)
    faces[s] = {vertex(0, 0, depth[s]), vertex(1, 0, depth[s]), vertex(1, 1, depth[s]), vertex(0, 1, depth[s])};
  faces[2] = {vertex(0, 0, f.near), vertex(0, 1, f.near), vertex(0, 1, f.far), vertex(0, 0, f.far)};
  faces[3] = {vertex(1, 0, f.near), vertex(1, 1, f.near), vertex(1, 1, f.far), vertex(1, 0, f.far)};
  faces[4] = {vertex(0, 0, f.near), vertex(1, 0, f.near), vertex(1, 0, f.far), vertex(0, 0, f.far)};
  faces[5] = {vertex(0, 1, f.near), vertex(1, 1, f.near), vertex(1, 1, f.far), vertex(0, 1, f.far)};
  for (int s = 0; s < 2; ++s)
    for (const glm::dvec3& p : faces[s]) cell.centre += p / 8.0;
  for (int s = 0; s < 2; ++s)
    for (const glm::dvec3& p : faces[s]) cell.radius = std::max(cell.radius, glm::length(p - cell.centre));
  return cell;
}

inline double point_quad_distance(const glm::dvec3& p, const std::array<glm::dvec3, 4>& q) {
  double edges = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) edges = std::min(edges, point_segment_distance(p, q[i], q[(i + 1) % 4]));
  glm::dvec3 n = glm::cross(q[1] - q[0], q[2] - q[0]);
  if (!(glm::length(n) > 0)) n = glm::cross(q[2] - q[0], q[3] - q[0]);
  const double length = glm::length(n);
  if (!(length > 0)) return edges;  // a degenerate face: its edges are all of it
  n /= length;
  const glm::dvec3 projected = p - glm::dot(p - q[0], n) * n;
  int positive = 0, negative = 0;
  for (int i = 0; i < 4; ++i) {
    const double side = glm::dot(glm::cross(q[(i + 1) % 4] - q[i], projected - q[i]), n);
    positive += side >= 0;
    negative += side <= 0;
  }
  if (positive == 4 || negative == 4) return std::abs(glm::dot(p - q[0], n));
  return edges;
}

inline double point_cell_distance(const Froxel& f, const FroxelCell& cell, const glm::dvec3& p) {
  const double depth = -p.z;
  bool inside = depth >= f.near && depth <= f.far;
  for (const glm::dvec3& n : f.planes) inside = inside && glm::dot(n, p) >= 0;
  if (inside) return 0;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& face : cell.faces) best = std::min(best, point_quad_distance(p, face));
  return best;
}

// Exact distance from the light's core to the froxel's cell (convex in the segment parameter).
inline double core_cell_distance(const Froxel& f, const FroxelCell& cell, const LightCore& c) {
  auto at = [&](double t) { return point_cell_distance(f, cell, c.a + t * (c.b - c.a)); };
  if (c.a == c.b) return at(0);
  const double phi = (std::sqrt(5.0) - 1) / 2;
  double lo = 0, hi = 1, x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo), f1 = at(x1), f2 = at(x2);
  while (hi - lo > 0x1p-40) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - phi * (hi - lo);
      f1 = at(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + phi * (hi - lo);
      f2 = at(x2);
    }
  }
  return std::min({f1, f2, at(0), at(1)});
}

inline bool truly_reaches(const Froxel& f, const FroxelCell& cell, const LightCore& c) {
  if (!f.occupied || c.reach == LightCore::Reach::none) return false;
  if (c.reach == LightCore::Reach::everywhere) return true;
  if (point_segment_distance(cell.centre, c.a, c.b) > c.range + cell.radius) return false;
  return core_cell_distance(f, cell, c) <= c.range;
}

}  // namespace nightcap::reference
