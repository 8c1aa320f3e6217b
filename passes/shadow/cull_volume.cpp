// The slice extruded toward the sun as a convex volume of at most kMaxPlanes planes.
#include "passes/shadow/cull_volume.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace nightcap::shadow_cull {

constexpr uint32_t kMaxPlanes = 8;

Volume extruded_slice(const Corners& c, const dvec3& to_sun, double margin, double depth_margin) {
  // Faces as corner loops, and the slice's centre to orient each plane inward.
  static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  dvec3 centre(0.0);
  for (const dvec3& p : c) centre += p / 8.0;
  auto inward = [&](dvec3 normal, const dvec3& through) {
    normal = glm::normalize(normal);
    if (glm::dot(normal, centre - through) < 0) normal = -normal;
    return Plane{normal, -glm::dot(normal, through)};
  };
  std::array<Plane, 6> faces;
  std::array<bool, 6> kept{};
  std::vector<std::pair<double, Plane>> face_planes;  // (face area, plane): the smallest dropped first past 8
  for (int f = 0; f < 6; ++f) {
    const dvec3 &a = c[kFaces[f][0]], &b = c[kFaces[f][1]], &d = c[kFaces[f][3]], &e = c[kFaces[f][2]];
    const dvec3 cross = glm::cross(e - a, d - b);
    faces[f] = inward(cross, a);
    // Extruding toward the sun never leaves a face's half-space when its inward normal has no
    // component against the sun's direction.
    kept[f] = glm::dot(faces[f].normal, to_sun) >= -1e-12;
    if (kept[f]) face_planes.push_back({glm::length(cross), faces[f]});
  }
  Volume v;
  // Silhouette edges: shared by a kept face and a dropped one.
  for (int f = 0; f < 6; ++f) {
    if (!kept[f]) continue;
    for (int g = 0; g < 6; ++g) {
      if (kept[g]) continue;
      int shared[2], n = 0;
      for (int i : kFaces[f])
        for (int j : kFaces[g])
          if (i == j && n < 2) shared[n++] = i;
      if (n != 2) continue;
      const dvec3 normal = glm::cross(c[shared[1]] - c[shared[0]], to_sun);
      if (glm::dot(normal, normal) < 1e-24) continue;
      v.planes.push_back(inward(normal, c[shared[0]]));
    }
  }
  // Dropping a plane only enlarges the volume: past 8, the smallest faces go first.
  std::sort(face_planes.begin(), face_planes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [area, plane] : face_planes)
    if (v.planes.size() < kMaxPlanes) v.planes.push_back(plane);
  for (Plane& p : v.planes) p.offset += margin + depth_margin * std::max(0.0, glm::dot(p.normal, to_sun));
  return v;
}

}  // namespace nightcap::shadow_cull
