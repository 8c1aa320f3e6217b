#include "passes/frame/occlusion_buffer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "passes/core/graph.h"

namespace nightcap {
namespace {

// Clip space → the buffer's continuous coordinates (cell (i, j) spans [i, i+1] × [j, j+1]) and
// device depth, as the viewport transform maps them: y grows downward in the framebuffer, and
// the projection already flipped it.
struct Projected {
  double x, y, depth;
};

Projected project(const glm::dvec4& clip, uint32_t width, uint32_t height) {
  return {(clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height, clip.z / clip.w};
}

// Points within this many cells of an edge count as outside, so the GPU's own rounding of the
// vertex positions cannot uncover a cell the buffer treats as covered.
constexpr double kEdgeMargin = 1e-3;

}  // namespace

OcclusionBuffer::OcclusionBuffer(uint32_t width, uint32_t height)
    : width_(width), height_(height), depth_(size_t(width) * height, 0.0f) {}

OcclusionBuffer OcclusionBuffer::from_record(std::span<const uint8_t> bytes) {
  OcclusionHeader header{};
  if (bytes.size() < sizeof(header)) throw GraphError("cull.occlusion: no header");
  std::memcpy(&header, bytes.data(), sizeof(header));
  if (header.width == 0 || header.height == 0 || header.width > 4096 || header.height > 4096 ||
      bytes.size() != sizeof(header) + uint64_t(header.width) * header.height * 4)
    throw GraphError("cull.occlusion: its header does not match its size (" + std::to_string(bytes.size()) + " bytes)");
  OcclusionBuffer buffer(header.width, header.height);
  std::memcpy(buffer.depth_.data(), bytes.data() + sizeof(header), buffer.depth_.size() * 4);
  return buffer;
}

// The sum is glm's mat4 × vec4, ((m0·x + m1·y) + (m2·z + m3)), so the corners are the
// same bits as one product each; the products corners share are computed once.
void box_corners(const glm::dmat4& m, const glm::dvec3& lo, const glm::dvec3& hi, glm::dvec4 (&out)[8]) {
  const glm::dvec4 x[2] = {m[0] * lo.x, m[0] * hi.x};
  const glm::dvec4 y[2] = {m[1] * lo.y, m[1] * hi.y};
  const glm::dvec4 zw[2] = {m[2] * lo.z + m[3], m[2] * hi.z + m[3]};
  for (int k = 0; k < 8; ++k) out[k] = (x[k & 1] + y[(k >> 1) & 1]) + zw[(k >> 2) & 1];
}

bool outside_frustum(const glm::dvec4 (&c)[8]) {
  int outside[5] = {0, 0, 0, 0, 0};
  for (const glm::dvec4& p : c) {
    outside[0] += p.x < -p.w;
    outside[1] += p.x > p.w;
    outside[2] += p.y < -p.w;
    outside[3] += p.y > p.w;
    outside[4] += p.z > p.w;  // in front of the near plane (reversed-Z: z = znear, w = -z_view)
  }
  return std::any_of(std::begin(outside), std::end(outside), [](int n) { return n == 8; });
}

void OcclusionBuffer::rasterise(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c,
                                bool front_counter_clockwise, bool two_sided) {
  // Within a hair of the camera plane the projection is unreliable, and the GPU clips there.
  const double near_w = 1e-6;
  if (a.w <= near_w || b.w <= near_w || c.w <= near_w || a.z > a.w || b.z > b.w || c.z > c.w) return;
  const Projected p[3] = {project(a, width_, height_), project(b, width_, height_), project(c, width_, height_)};
  // Vulkan's signed area: positive is counter-clockwise in framebuffer coordinates.
  const double area = -0.5 * ((p[0].x * p[1].y - p[1].x * p[0].y) + (p[1].x * p[2].y - p[2].x * p[1].y) +
                              (p[2].x * p[0].y - p[0].x * p[2].y));
  if (!std::isfinite(area) || area == 0.0) return;
  if (!two_sided && (area > 0.0) != front_counter_clockwise) return;
  // Edge functions oriented so the inside is positive whatever the winding.
  const double sign = area > 0.0 ? -1.0 : 1.0;
  struct Edge {
    double a, b, c, scale;
  } edges[3];
  for (int e = 0; e < 3; ++e) {
    const Projected &u = p[e], &v = p[(e + 1) % 3];
    Edge& edge = edges[e];
    edge.a = sign * (u.y - v.y);
    edge.b = sign * (v.x - u.x);
    edge.c = sign * (u.x * v.y - v.x * u.y);
    edge.scale = std::hypot(edge.a, edge.b);
  }
  // The depth plane through the three projected vertices.
  const double det = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  const double dzdx =
      ((p[1].depth - p[0].depth) * (p[2].y - p[0].y) - (p[2].depth - p[0].depth) * (p[1].y - p[0].y)) / det;
  const double dzdy =
      ((p[2].depth - p[0].depth) * (p[1].x - p[0].x) - (p[1].depth - p[0].depth) * (p[2].x - p[0].x)) / det;
  if (!std::isfinite(dzdx) || !std::isfinite(dzdy)) return;
  const double lo_x = std::min({p[0].x, p[1].x, p[2].x}), hi_x = std::max({p[0].x, p[1].x, p[2].x});
  const double lo_y = std::min({p[0].y, p[1].y, p[2].y}), hi_y = std::max({p[0].y, p[1].y, p[2].y});
  const int x0 = std::max(0, int(std::ceil(std::max(lo_x, -1.0)))),
            x1 = std::min(int(width_), int(std::floor(std::min(hi_x, double(width_) + 1))));
  const int y0 = std::max(0, int(std::ceil(std::max(lo_y, -1.0)))),
            y1 = std::min(int(height_), int(std::floor(std::min(hi_y, double(height_) + 1))));
  // Row by row: a cell [x, x+1] × [y, y+1] is whole inside when its four corners are, and each
  // edge function is linear, so on the row's two boundary lines every edge bounds x to one side.
  for (int y = y0; y < y1; ++y) {
    double from = x0, to = x1 - 1;  // the cells' left corners x may take
    for (const Edge& e : edges) {
      // e.a·x + e.b·y' + e.c ≥ margin for y' = y and y + 1, at x and at x + 1.
      const double need = kEdgeMargin * e.scale - e.c - e.b * (e.b > 0 ? y : y + 1);
      if (e.a > 0) {
        from = std::max(from, std::ceil(need / e.a));
      } else if (e.a < 0) {
        to = std::min(to, std::floor(need / e.a) - 1);
      } else if (need > 0) {
        to = from - 1;
      }
    }
    for (int x = int(from); x <= int(to); ++x) {
      // The farthest (smallest) device depth of the plane over the cell.
      const double z = p[0].depth + dzdx * (x - p[0].x) + dzdy * (y - p[0].y);
      const double farthest = z + std::min(0.0, dzdx) + std::min(0.0, dzdy);
      // The nearest of the triangles covering the cell wins, whatever order they come in.
      const float value = float(farthest * (1.0 - kMargin));
      float& cell = depth_[size_t(y) * width_ + x];
      cell = std::max(cell, value);
    }
  }
}

bool OcclusionBuffer::hidden(const glm::dvec4 (&corners)[8]) const {
  double lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY, nearest = 0.0;
  for (const glm::dvec4& c : corners) {
    if (!(c.w > 1e-6)) return false;  // reaches the camera plane: cannot be judged here
    const Projected p = project(c, width_, height_);
    lo_x = std::min(lo_x, p.x);
    hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y);
    hi_y = std::max(hi_y, p.y);
    nearest = std::max(nearest, p.depth);
  }
  if (!std::isfinite(lo_x + hi_x + lo_y + hi_y + nearest)) return false;
  const int x0 = std::max(0, int(std::floor(lo_x))), x1 = std::min(int(width_) - 1, int(std::floor(hi_x)));
  const int y0 = std::max(0, int(std::floor(lo_y))), y1 = std::min(int(height_) - 1, int(std::floor(hi_y)));
  if (x0 > x1 || y0 > y1) return false;
  const double needed = nearest * (1.0 + kMargin);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (!(double(depth_[size_t(y) * width_ + x]) > needed)) return false;
  return true;
}

}  // namespace nightcap
