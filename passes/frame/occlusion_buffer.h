// The occlusion buffer of cull.main: a small CPU depth raster of the best occluders, in the
// frame's reversed-Z device depth (1 near, 0 at infinity).
//
// It is conservative, so culling against it never removes a visible pixel:
// - a cell takes a triangle only where the triangle covers the whole cell, and then the
//   triangle's farthest depth over the cell (depth is affine in screen space, so the extreme
//   is at a corner);
// - only triangles the GPU rasterises are taken: back faces are skipped where the draw culls
//   them, triangles reaching the near plane are skipped;
// - a box is hidden only when its nearest corner is farther, by a relative margin that covers
//   the GPU's float rounding of both depths, than every cell its screen rectangle touches.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace nightcap {

// cull.occlusion, as recorded: this header, then width × height floats of reversed-Z device
// depth, row by row from the top (0 where no occluder covers a cell). frame.constants culls
// lights against it, so it lives with what the stages share.
struct OcclusionHeader {
  uint32_t width, height;
};

class OcclusionBuffer {
 public:
  // A buffer of width × height cells over the whole view.
  OcclusionBuffer(uint32_t width, uint32_t height);
  // A recorded buffer (cull.occlusion); throws GraphError when the bytes do not hold one.
  static OcclusionBuffer from_record(std::span<const uint8_t> bytes);

  // A triangle in clip space. `front_counter_clockwise`: the winding the draw treats as front
  // (Vulkan's convention, framebuffer y downward); `two_sided`: the draw culls no face.
  void rasterise(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c, bool front_counter_clockwise,
                 bool two_sided);
  // True when every point of the convex hull of the eight clip-space corners is certainly behind
  // the occluders.
  bool hidden(const glm::dvec4 (&corners)[8]) const;

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  std::span<const float> depth() const { return depth_; }

  // How much nearer, relatively, an occluder cell must be than a box to hide it.
  static constexpr double kMargin = 1e-5;

 private:
  uint32_t width_, height_;
  std::vector<float> depth_;  // 0 where nothing covers the cell
};

// Conservative: true only when all eight clip-space corners lie outside one clip plane (left,
// right, bottom, top, or in front of the near plane; the far plane is at infinity).
bool outside_frustum(const glm::dvec4 (&corners)[8]);

// clip_from_box × (x, y, z, 1) at the box's eight corners (bit k of a corner's index: the max
// on axis k), as outside_frustum() and OcclusionBuffer::hidden() take them.
void box_corners(const glm::dmat4& clip_from_box, const glm::dvec3& lo, const glm::dvec3& hi, glm::dvec4 (&out)[8]);

}  // namespace nightcap
