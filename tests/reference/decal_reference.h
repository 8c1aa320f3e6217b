// A CPU reference for decals.projected, shared by the unit test and the benchmark: a plain scene
// (a ground slab, a static box and a box moving across the decal, all axis-aligned boxes) whose
// every pixel centre is ray-cast analytically in double precision, giving the true surface point
// the depth buffer describes and whether the surface is moving. A projected decal covers a pixel
// when that point lies inside its box (|local| ≤ 0.5 on every axis) and the surface does not
// move (frame.md: decals do not apply on pixels tagged moving).
#pragma once

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <vector>

#include "passes/scene/scene.h"
#include "passes/scene/scene_kit.h"

namespace nightcap::reference {

struct DecalTestBox {
  glm::dvec3 centre, half;
  bool moving = false;
};

struct DecalTestScene {
  Scene scene;
  std::vector<DecalTestBox> boxes;  // what the scene's instances are, at time 0
};

// The ground's top at y = 0, a green static box beside the origin, a blue box moving along +x
// through it (its position at frame 0 is where it stands), the camera 5 m up looking at the
// origin from 8 m away. No decal: the caller adds those it tests.
inline DecalTestScene decal_test_scene() {
  DecalTestScene out;
  Scene& scene = out.scene;
  scene.source = "decal reference";
  scene_kit::Builder build(scene);
  auto add = [&](const glm::dvec3& centre, const glm::dvec3& half, glm::vec3 colour, bool moving) {
    const uint32_t material = build.material(scene_kit::plain("box", colour, 0.0f, 0.8f, stencil::plain));
    Instance& instance = build.place(build.box(glm::vec3(half), material, 1.0f, true, true), centre);
    instance.moving = moving;
    if (moving) instance.velocity = {1.0f, 0.0f, 0.0f};
    out.boxes.push_back({centre, half, moving});
  };
  add({0.0, -0.05, 0.0}, {30.0, 0.05, 30.0}, {0.5f, 0.5f, 0.5f}, false);
  add({2.2, 1.0, 0.0}, {1.0, 1.0, 1.0}, {0.2f, 0.6f, 0.2f}, false);
  add({-0.5, 0.5, 0.3}, {0.5, 0.5, 0.5}, {0.1f, 0.1f, 0.8f}, true);
  scene.lights.push_back(scene_kit::moon());
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  camera.world = glm::inverse(glm::lookAt(glm::dvec3(0.0, 5.0, 8.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  return out;
}

// The decal box the tests project: 4 m × 3 m across the ground, 1.5 m tall, turned 30° about
// the vertical, reaching into the static box's side and around the moving box.
inline glm::dmat4 decal_test_box() {
  return glm::scale(glm::rotate(glm::rotate(glm::translate(glm::dmat4(1.0), {0.5, 0.25, 0.0}), glm::radians(30.0),
                                            glm::dvec3(0, 1, 0)),
                                -glm::half_pi<double>(), glm::dvec3(1, 0, 0)),
                    glm::dvec3(4.0, 3.0, 1.5));
}

struct RayHit {
  glm::dvec3 position;  // world
  double distance = 0;  // along the ray
  int box = -1;         // index into DecalTestScene::boxes
  bool moving = false;
  double cos_incidence = 1;  // |cos| of the angle between the ray and the face it hit
};

struct Ray {
  glm::dvec3 origin, direction;  // direction: unit length
};

// The ray through the centre of pixel (x, y) of a width × height image (y down).
inline Ray pixel_ray(const Camera& camera, uint32_t width, uint32_t height, uint32_t x, uint32_t y) {
  const double t = std::tan(double(camera.yfov) / 2), aspect = double(width) / height;
  const double u = (2.0 * (x + 0.5) / width - 1.0) * t * aspect, v = (1.0 - 2.0 * (y + 0.5) / height) * t;
  return {glm::dvec3(camera.world[3]), glm::normalize(glm::dmat3(camera.world) * glm::dvec3(u, v, -1.0))};
}

// The surface seen through the centre of pixel (x, y) of a width × height image.
inline std::optional<RayHit> cast_pixel(const DecalTestScene& s, const Camera& camera, uint32_t width, uint32_t height,
                                        uint32_t x, uint32_t y) {
  const Ray ray = pixel_ray(camera, width, height, x, y);
  const glm::dvec3 eye = ray.origin, dir = ray.direction;
  std::optional<RayHit> best;
  for (size_t b = 0; b < s.boxes.size(); ++b) {
    const glm::dvec3 lo = s.boxes[b].centre - s.boxes[b].half, hi = s.boxes[b].centre + s.boxes[b].half;
    double near = -INFINITY, far = INFINITY;
    int axis = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = (lo[k] - eye[k]) / dir[k], c = (hi[k] - eye[k]) / dir[k];
      if (std::min(a, c) > near) axis = k;
      near = std::max(near, std::min(a, c));
      far = std::min(far, std::max(a, c));
    }
    if (near > far || near <= 0.0) continue;
    if (!best || near < best->distance)
      best = RayHit{eye + dir * near, near, int(b), s.boxes[b].moving, std::abs(dir[axis])};
  }
  return best;
}

// The point in the decal box's unit cube.
inline glm::dvec3 decal_local(const glm::dmat4& box, const glm::dvec3& world) {
  return glm::dvec3(glm::inverse(box) * glm::dvec4(world, 1.0));
}

// How far (metres) a world point lies from the nearest face of the box, inside or out.
inline double distance_to_faces(const glm::dmat4& box, const glm::dvec3& world) {
  const glm::dvec3 local = decal_local(box, world);
  double nearest = INFINITY;
  for (int k = 0; k < 3; ++k) nearest = std::min(nearest, std::abs(0.5 - std::abs(local[k])) * glm::length(box[k]));
  return nearest;
}

}  // namespace nightcap::reference
