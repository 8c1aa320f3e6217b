// cull.main's occlusion buffer against a ray-cast reference. Random triangles are rasterised;
// for every random box the buffer calls hidden, 256 random points of the box are checked one by
// one: some rasterised, front-facing triangle must cover the point's screen position nearer than
// the point (depth from the triangle's own plane, in double precision). Stated tolerance: none —
// a single visible point of a hidden box fails. The test also asks that the buffer hides a fair
// share of the boxes (it would pass trivially otherwise), and that a back face the draw culls
// hides nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "passes/frame/occlusion_buffer.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

struct Triangle {
  glm::dvec4 v[3];
};

// Where the triangle covers normalised device position (x, y), its device depth there.
std::optional<double> depth_at(const Triangle& t, double x, double y) {
  glm::dvec3 p[3];
  for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(t.v[k]) / t.v[k].w;
  const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  const double b1 = ((x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (y - p[0].y)) / area;
  const double b2 = ((p[1].x - p[0].x) * (y - p[0].y) - (x - p[0].x) * (p[1].y - p[0].y)) / area;
  const double b0 = 1.0 - b1 - b2;
  if (b0 < 0 || b1 < 0 || b2 < 0) return std::nullopt;
  return b0 * p[0].z + b1 * p[1].z + b2 * p[2].z;
}

// A perspective-like clip position: x, y in view, depth z/w = znear / distance.
glm::dvec4 clip(double x_ndc, double y_ndc, double distance) {
  const double w = distance;
  return {x_ndc * w, y_ndc * w, 0.1, w};
}

TEST(OcclusionBuffer, HiddenBoxesHaveNoVisiblePoint) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t hidden = 0, boxes = 0;
  for (int scene = 0; scene < 40; ++scene) {
    OcclusionBuffer buffer(64 + scene % 7, 36 + scene % 5);
    std::vector<Triangle> front;
    for (int k = 0; k < 12; ++k) {
      Triangle t;
      const double cx = unit(rng) * 2 - 1, cy = unit(rng) * 2 - 1, size = 0.3 + unit(rng);
      const double distance = 2 + unit(rng) * 20, slope = (unit(rng) - 0.5) * 4;
      for (int v = 0; v < 3; ++v) {
        const double angle = v * 2.0944 + unit(rng) * 0.5;
        const double x = cx + size * std::cos(angle), y = cy + size * std::sin(angle);
        t.v[v] = clip(x, y, std::max(0.5, distance + slope * x));
      }
      const bool ccw = unit(rng) < 0.5;
      buffer.rasterise(t.v[0], t.v[1], t.v[2], ccw, false);
      // What the buffer should have taken: Vulkan's signed area in framebuffer coordinates.
      glm::dvec2 p[3];
      for (int v = 0; v < 3; ++v) p[v] = glm::dvec2(t.v[v]) / t.v[v].w;
      const double area = -((p[0].x * p[1].y - p[1].x * p[0].y) + (p[1].x * p[2].y - p[2].x * p[1].y) +
                            (p[2].x * p[0].y - p[0].x * p[2].y));
      if ((area > 0) == ccw) front.push_back(t);
    }
    for (int b = 0; b < 200; ++b) {
      const double cx = unit(rng) * 2 - 1, cy = unit(rng) * 2 - 1, cz = 3 + unit(rng) * 40;
      const double hx = 0.05 + unit(rng) * 0.3, hy = 0.05 + unit(rng) * 0.3, hz = unit(rng) * 3;
      glm::dvec4 corners[8];
      for (int k = 0; k < 8; ++k)
        corners[k] = clip(cx + (k & 1 ? hx : -hx), cy + (k & 2 ? hy : -hy), cz + (k & 4 ? hz : -hz));
      ++boxes;
      if (!buffer.hidden(corners)) continue;
      ++hidden;
      for (int s = 0; s < 256; ++s) {
        const double x = cx + (unit(rng) * 2 - 1) * hx, y = cy + (unit(rng) * 2 - 1) * hy;
        const double z = 0.1 / (cz + (unit(rng) * 2 - 1) * hz);
        if (std::abs(x) > 1 || std::abs(y) > 1) continue;  // off screen: never drawn
        bool covered = false;
        for (const Triangle& t : front)
          if (auto d = depth_at(t, x, y); d && *d > z) covered = true;
        ASSERT_TRUE(covered) << "scene " << scene << " box " << b << ": point (" << x << ", " << y << ", " << z
                             << ") of a hidden box is visible";
      }
    }
  }
  EXPECT_GT(hidden, boxes / 20) << "the buffer hid almost nothing";
  std::printf("occlusion buffer: %zu of %zu boxes hidden\n", hidden, boxes);
}

TEST(OcclusionBuffer, CulledBackFacesHideNothing) {
  // One triangle over the whole view, close, and a box far behind it.
  const glm::dvec4 a = clip(-3, -3, 1), b = clip(3, -3, 1), c = clip(0, 3, 1);
  glm::dvec4 corners[8];
  for (int k = 0; k < 8; ++k) corners[k] = clip(k & 1 ? 0.1 : -0.1, k & 2 ? 0.1 : -0.1, k & 4 ? 50 : 40);
  for (bool ccw : {true, false}) {
    OcclusionBuffer front(32, 32), back(32, 32), both(32, 32);
    // (a, b, c) in framebuffer coordinates (y down) is clockwise: front for a clockwise draw.
    front.rasterise(a, b, c, ccw, false);
    both.rasterise(a, b, c, ccw, true);
    EXPECT_EQ(front.hidden(corners), !ccw) << (ccw ? "a culled back face occluded" : "a front face did not occlude");
    EXPECT_TRUE(both.hidden(corners)) << "a two-sided triangle did not occlude";
    EXPECT_FALSE(back.hidden(corners)) << "an empty buffer occluded";
  }
}

TEST(OcclusionBuffer, BoxesReachingTheCameraPlaneAreNeverHidden) {
  OcclusionBuffer buffer(16, 16);
  buffer.rasterise(clip(-3, -3, 1), clip(3, -3, 1), clip(0, 3, 1), false, true);
  glm::dvec4 corners[8];
  for (int k = 0; k < 8; ++k) corners[k] = clip(k & 1 ? 0.1 : -0.1, k & 2 ? 0.1 : -0.1, 5);
  corners[7].w = -1.0;  // behind the camera
  EXPECT_FALSE(buffer.hidden(corners));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
