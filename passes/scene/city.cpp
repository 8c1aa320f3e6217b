// The built-in scene: one Night City block at night. A grid of lots between wet streets,
// buildings of varied height whose facades carry lit windows, neon signs that are both
// emissive geometry and tube lights, street lamps, a few spot lights, parked cars and the
// moon. Everything derives from the seed through std::mt19937's raw output (its sequence is
// specified by the standard), so a seed gives the same city on every platform.
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "passes/scene/scene_kit.h"

namespace nightcap {

using namespace scene_kit;

Scene build_city(uint32_t seed) {
  Scene scene;
  scene.source = "built-in city (seed " + std::to_string(seed) + ")";
  Random random(seed);
  Builder build(scene);

  const std::vector<uint32_t> facades = facade_materials(random, build);
  const uint32_t roof = build.material(plain("roof", {0.12f, 0.12f, 0.13f}, 0.0f, 0.8f, stencil::plain));
  const uint32_t road = build.material(plain("road.wet_asphalt", {0.05f, 0.05f, 0.055f}, 0.0f, 0.25f, stencil::road));
  const uint32_t sidewalk = build.material(plain("sidewalk", {0.22f, 0.21f, 0.2f}, 0.0f, 0.7f, stencil::plain));
  const uint32_t pole = build.material(plain("lamp.pole", {0.3f, 0.3f, 0.32f}, 1.0f, 0.4f, stencil::plain));

  // 3×3 lots of 48 m between 16 m streets: the block spans about 176 m.
  constexpr double kLot = 48.0, kStreet = 16.0, kPitch = kLot + kStreet;
  constexpr int kLots = 3;
  const double extent = kLots * kPitch + kStreet;
  build.place(build.box({float(extent / 2), 0.05f, float(extent / 2)}, road, 0.25f), {0.0, -0.05, 0.0});

  for (int gx = 0; gx < kLots; ++gx)
    for (int gz = 0; gz < kLots; ++gz) {
      const glm::dvec3 lot_centre((gx - 1) * kPitch, 0.0, (gz - 1) * kPitch);
      build.place(build.box({float(kLot / 2 + 2), 0.075f, float(kLot / 2 + 2)}, sidewalk, 0.5f),
                  lot_centre + glm::dvec3(0, 0.075, 0));
      // One to four buildings per lot, tallest toward the middle of the block.
      const int count = 1 + int(random.below(4));
      for (int b = 0; b < count; ++b) {
        const double w = count == 1 ? random.range(30, 44) : random.range(14, 22);
        const double d = count == 1 ? random.range(30, 44) : random.range(14, 22);
        const double centrality = (gx == 1 && gz == 1) ? 1.0 : 0.55;
        const double h = random.range(10.0, 120.0 * centrality);
        const double ox = count == 1 ? 0.0 : ((b & 1) ? 1 : -1) * (kLot / 4);
        const double oz = count == 1 ? 0.0 : ((b & 2) ? 1 : -1) * (kLot / 4);
        const glm::dvec3 centre = lot_centre + glm::dvec3(ox, 0.15 + h / 2, oz);
        build.place(
            build.box({float(w / 2), float(h / 2), float(d / 2)}, facades[random.below(3)], 1.0f / 16.0f, false),
            centre);
        build.place(build.box({float(w / 2), 0.1f, float(d / 2)}, roof, 0.25f), centre + glm::dvec3(0, h / 2 + 0.1, 0));

        // Neon signs on the facade facing the nearest street: an emissive bar and its tube light.
        const int signs = int(random.below(4));
        for (int s = 0; s < signs; ++s) {
          const glm::vec3 colour = kNeon[random.below(uint32_t(kNeon.size()))];
          Material neon = plain("neon", colour * 0.2f, 0.0f, 0.3f, stencil::plain);
          neon.emissive = colour;
          neon.emissive_strength = 40.0f;
          const uint32_t material = build.material(neon);
          const double length = random.range(2.0, 8.0);
          const double y = random.range(4.0, std::max(5.0, std::min(h - 2.0, 30.0)));
          const bool vertical = random.uniform() < 0.4;
          const int face = int(random.below(4));
          const glm::dvec3 normal = face == 0   ? glm::dvec3(1, 0, 0)
                                    : face == 1 ? glm::dvec3(-1, 0, 0)
                                    : face == 2 ? glm::dvec3(0, 0, 1)
                                                : glm::dvec3(0, 0, -1);
          const glm::dvec3 along = vertical ? glm::dvec3(0, 1, 0) : glm::dvec3(normal.z, 0, -normal.x);
          const glm::dvec3 surface = centre + normal * (glm::abs(normal.x) > 0 ? w / 2 + 0.3 : d / 2 + 0.3);
          const glm::dvec3 mid(surface.x, y, surface.z);
          const glm::vec3 half =
              glm::vec3(glm::abs(along) * (length / 2) + glm::abs(normal) * 0.06 +
                        (vertical ? glm::abs(glm::dvec3(normal.z, 0, normal.x)) : glm::dvec3(0, 1, 0)) * 0.06);
          build.place(build.box(half, material, 1.0f, true, true), mid);
          scene.lights.push_back(neon_tube(mid - along * (length / 2), mid + along * (length / 2), colour, 40.0f));
        }
      }
    }

  // Street lamps along the streets between lots, and cars parked at the kerbs.
  for (int line = 0; line <= kLots; ++line) {
    const double street = (line - 1.5) * kPitch;
    for (int k = 0; k < kLots; ++k) {
      const double along = (k - 1) * kPitch;
      const bool x_street = (line + k) % 2 == 0;
      const glm::dvec3 base = x_street ? glm::dvec3(along, 0.0, street + kStreet / 2 - 1.0)
                                       : glm::dvec3(street + kStreet / 2 - 1.0, 0.0, along);
      build.place(build.box({0.08f, 3.0f, 0.08f}, pole, 1.0f), base + glm::dvec3(0, 3.0, 0));
      scene.lights.push_back(street_lamp(base + glm::dvec3(0, 6.2, 0), 35.0f));
    }
  }
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 paint = kNeon[random.below(uint32_t(kNeon.size()))] * 0.5f + glm::vec3(0.05f);
    const uint32_t material = build.material(plain("car.paint", paint, 0.9f, 0.25f, stencil::vehicle));
    const int line = int(random.below(kLots + 1));
    const double street = (line - 1.5) * kPitch;
    const double along = random.range(-extent / 2 + 10, extent / 2 - 10);
    const bool x_street = random.uniform() < 0.5;
    const double kerb = street + (random.uniform() < 0.5 ? -1 : 1) * (kStreet / 2 - 2.5);
    const glm::dvec3 centre = x_street ? glm::dvec3(along, 0.0, kerb) : glm::dvec3(kerb, 0.0, along);
    const double yaw = x_street ? 0.0 : glm::half_pi<double>();
    build.place(build.box({2.25f, 0.55f, 0.95f}, material, 1.0f, true), centre + glm::dvec3(0, 0.75, 0), yaw);
    build.place(build.box({1.2f, 0.35f, 0.85f}, material, 1.0f, true), centre + glm::dvec3(0, 1.65, 0), yaw);
  }
  // Spot lights washing three facades from above the street.
  for (int s = 0; s < 3; ++s) {
    Light spot;
    spot.type = LightType::spot;
    spot.position = glm::dvec3((s - 1) * kPitch, 12.0, -kPitch / 2);
    spot.direction = glm::normalize(glm::vec3(0.0f, -1.0f, -0.6f));
    spot.color = kNeon[(s * 2) % kNeon.size()];
    spot.intensity = 3000.0f;
    spot.range = 60.0f;
    spot.inner_cone = 0.25f;
    spot.outer_cone = 0.5f;
    scene.lights.push_back(spot);
  }
  scene.lights.push_back(moon());

  // Street level, looking down a street toward the tall middle of the block.
  Camera camera;
  const glm::dvec3 eye(-1.5 * kPitch + 3.0, 7.0, kPitch * 0.5 + 2.0);
  const glm::dvec3 target(0.5 * kPitch, 22.0, -kPitch * 0.2);
  camera.world = glm::inverse(glm::lookAt(eye, target, glm::dvec3(0, 1, 0)));
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  scene.camera = camera;
  scene.probes = probe_in_bounds(scene);
  return scene;
}

}  // namespace nightcap
