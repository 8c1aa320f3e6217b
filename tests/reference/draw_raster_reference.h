// A CPU reference for what the geometry pass (gbuffer.opaque) rasterises at each pixel centre,
// for `inspect pick`'s test, written from Vulkan's rules rather than from the pass's code:
//
// - each draw's triangles placed as geometry.glsl places them (the position decoded in the
//   draw's box, the draw's model matrix, then the recorded camera's projection · view), in
//   double precision;
// - clipped to the view volume's depth range 0 ≤ z ≤ w (reversed-Z: the near plane is z = w),
//   then fanned into triangles in front of the camera;
// - culled as draw_scene culls: back faces go, unless the material is double-sided; a front face
//   winds counter-clockwise in framebuffer coordinates, clockwise when the draw mirrors;
// - a pixel centre (x + ½, y + ½) is covered when it lies inside the triangle; its depth is the
//   device depth z/w interpolated linearly in screen space (Vulkan's rule for depth).
//
// A centre within kEdgeSlack pixels of an edge is covered or not by the GPU's rounding (lavapipe
// snaps vertices to 1/256 pixel): such a hit is marked unsure.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <vector>

#include "captures/capture.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/vertex_streams.h"

namespace nightcap::reference {

inline constexpr double kEdgeSlack = 0x1p-6;  // pixels: four times lavapipe's 1/256 vertex snap

// One triangle of one draw, front-facing and in front of the camera, in pixel coordinates.
struct ScreenTriangle {
  uint32_t draw = 0;
  std::array<glm::dvec2, 3> pixel;  // framebuffer position of each vertex
  std::array<double, 3> depth;      // device depth z/w of each vertex
};

// A triangle covering a pixel centre.
struct Hit {
  uint32_t draw = 0;
  double depth = 0;   // device depth at the centre (reversed-Z: larger is nearer)
  bool sure = false;  // inside by more than kEdgeSlack
};

namespace detail {

template <typename T>
T read(const std::vector<uint8_t>& raw, uint64_t offset) {
  T value;
  std::memcpy(&value, raw.data() + offset, sizeof(T));
  return value;
}

// Sutherland–Hodgman against the half-space dot(plane, v) ≥ 0.
inline std::vector<glm::dvec4> clip(const std::vector<glm::dvec4>& polygon, const glm::dvec4& plane) {
  std::vector<glm::dvec4> out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec4& a = polygon[i];
    const glm::dvec4& b = polygon[(i + 1) % polygon.size()];
    const double da = glm::dot(plane, a), db = glm::dot(plane, b);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

}  // namespace detail

// Every front-facing triangle the draws put in front of the camera.
inline std::vector<ScreenTriangle> screen_triangles(const std::vector<GpuDraw>& draws,
                                                    const std::vector<GpuMaterial>& materials,
                                                    const std::vector<uint8_t>& geometry, const FrameRecord& frame) {
  const auto header = detail::read<GeometryHeader>(geometry, 0);
  glm::dmat4 view, projection;
  std::memcpy(&view[0][0], frame.camera.view.data(), sizeof(double) * 16);
  std::memcpy(&projection[0][0], frame.camera.projection.data(), sizeof(double) * 16);
  std::vector<ScreenTriangle> out;
  for (uint32_t d = 0; d < draws.size(); ++d) {
    const GpuDraw& draw = draws[d];
    const bool double_sided = (int(materials.at(draw.material).extra.w) & 2) != 0;
    const glm::dmat4 clip_from_object = projection * view * glm::dmat4(draw.model);
    for (uint32_t t = 0; t < draw.index_count / 3; ++t) {
      std::vector<glm::dvec4> polygon;
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t index =
            detail::read<uint32_t>(geometry, header.index_offset + 4 * uint64_t(draw.first_index + 3 * t + k));
        const Vertex vertex = geometry_vertex(geometry, index + draw.vertex_offset, glm::vec3(draw.position_origin),
                                              glm::vec3(draw.position_step));
        polygon.push_back(clip_from_object *
                          glm::dvec4(vertex.position[0], vertex.position[1], vertex.position[2], 1.0));
      }
      polygon = detail::clip(detail::clip(polygon, {0, 0, 1, 0}), {0, 0, -1, 1});
      if (polygon.size() < 3) continue;
      std::vector<glm::dvec2> pixel;
      std::vector<double> depth;
      for (const glm::dvec4& v : polygon) {
        pixel.emplace_back((v.x / v.w + 1) * 0.5 * frame.width, (v.y / v.w + 1) * 0.5 * frame.height);
        depth.push_back(v.z / v.w);
      }
      // Twice the signed area in framebuffer coordinates (y down): negative winds counter-
      // clockwise on screen, Vulkan's positive area. Clipping keeps the winding.
      double area = 0;
      for (size_t i = 0; i < pixel.size(); ++i) {
        const glm::dvec2 a = pixel[i], b = pixel[(i + 1) % pixel.size()];
        area += a.x * b.y - b.x * a.y;
      }
      const bool front = (area < 0) != (draw.mirrored != 0);
      if (area == 0 || (!front && !double_sided)) continue;
      for (size_t i = 1; i + 1 < pixel.size(); ++i)
        out.push_back({d, {pixel[0], pixel[i], pixel[i + 1]}, {depth[0], depth[i], depth[i + 1]}});
    }
  }
  return out;
}

// Whether the triangle covers the centre of pixel (x, y), and at what depth.
inline bool hit(const ScreenTriangle& t, uint32_t x, uint32_t y, Hit& result) {
  const glm::dvec2 p(x + 0.5, y + 0.5);
  auto cross = [](glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; };
  const double area = cross(t.pixel[1] - t.pixel[0], t.pixel[2] - t.pixel[0]);
  if (area == 0) return false;
  std::array<double, 3> weight;  // screen-space barycentrics
  double nearest_edge = INFINITY;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec2 a = t.pixel[(i + 1) % 3], b = t.pixel[(i + 2) % 3];
    weight[i] = cross(b - a, p - a) / area;
    nearest_edge = std::min(nearest_edge, weight[i] * std::abs(area) / glm::length(b - a));
  }
  if (nearest_edge < -kEdgeSlack) return false;
  result = {t.draw, weight[0] * t.depth[0] + weight[1] * t.depth[1] + weight[2] * t.depth[2],
            nearest_edge > kEdgeSlack};
  return true;
}

// Per pixel, row by row: every triangle covering its centre.
inline std::vector<std::vector<Hit>> rasterise(const std::vector<ScreenTriangle>& triangles, uint32_t width,
                                               uint32_t height) {
  std::vector<std::vector<Hit>> hits(size_t(width) * height);
  for (const ScreenTriangle& t : triangles) {
    double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
    for (const glm::dvec2& p : t.pixel) {
      lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
      lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
    }
    // Pixels whose centre can be within kEdgeSlack of the box, inside the image.
    const auto pixel_range = [](double lo, double hi, uint32_t size) {
      return std::pair(uint32_t(std::clamp(std::floor(lo - 1), 0.0, double(size))),
                       uint32_t(std::clamp(std::ceil(hi + 1), 0.0, double(size))));
    };
    const auto [x0, x1] = pixel_range(lo_x, hi_x, width);
    const auto [y0, y1] = pixel_range(lo_y, hi_y, height);
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x)
        if (Hit h; hit(t, x, y, h)) hits[size_t(y) * width + x].push_back(h);
  }
  return hits;
}

}  // namespace nightcap::reference
