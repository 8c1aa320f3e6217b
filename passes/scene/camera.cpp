#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "passes/scene/scene.h"

namespace nightcap {
namespace {

// Camera-to-world for an eye looking at a target (camera looks down its -Z, +Y up).
glm::dmat4 look_at(const glm::dvec3& eye, const glm::dvec3& target) {
  glm::dvec3 forward = glm::normalize(target - eye);
  // Looking straight up or down: any horizontal up keeps the basis well defined.
  const glm::dvec3 up = std::abs(forward.y) > 0.999999 ? glm::dvec3(0, 0, -forward.y) : glm::dvec3(0, 1, 0);
  return glm::inverse(glm::lookAt(eye, target, up));
}

}  // namespace

Camera orbit_camera(double theta_degrees, double phi_degrees, double radius, glm::dvec3 target, double yfov_degrees) {
  const double theta = glm::radians(theta_degrees), phi = glm::radians(phi_degrees);
  const glm::dvec3 eye =
      target + radius * glm::dvec3(std::sin(phi) * std::sin(theta), std::cos(phi), std::sin(phi) * std::cos(theta));
  Camera camera;
  camera.world = look_at(eye, target);
  camera.yfov = float(glm::radians(yfov_degrees));
  // A near plane proportional to the distance keeps small models sharp and big ones whole.
  camera.znear = float(std::max(1e-4, radius * 0.01));
  return camera;
}

Camera framing_camera(const Scene& scene, double aspect) {
  const glm::dvec3 lo = scene.bounds_min(), hi = scene.bounds_max();
  const glm::dvec3 centre = (lo + hi) * 0.5;
  const double radius = std::max(glm::length(hi - lo) * 0.5, 1e-3);
  const double yfov = glm::radians(45.0);
  const double half = std::min(yfov, 2.0 * std::atan(std::tan(yfov / 2.0) * aspect)) / 2.0;
  const double distance = radius / std::sin(half);
  Camera camera = orbit_camera(30.0, 70.0, distance, centre, 45.0);
  camera.znear = float(std::max(1e-4, (distance - radius) * 0.5));
  return camera;
}

namespace {

// World-space box around every instance's transformed primitive box.
std::pair<glm::dvec3, glm::dvec3> world_bounds(const Scene& scene) {
  if (scene.instances.empty()) return {glm::dvec3(0.0), glm::dvec3(0.0)};
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const Instance& instance : scene.instances) {
    const Primitive& p = scene.primitives.at(instance.primitive);
    // The box's centre moves with the transform; its half extent along each world axis is the
    // absolute basis times the object half extent.
    const glm::dvec3 centre(instance.world *
                            glm::dvec4(0.5 * (glm::dvec3(p.bounds_min) + glm::dvec3(p.bounds_max)), 1.0));
    const glm::dvec3 half = glm::dvec3(p.bounds_max - p.bounds_min) * 0.5;
    glm::dvec3 extent(0.0);
    for (int c = 0; c < 3; ++c) extent += glm::abs(glm::dvec3(instance.world[c])) * half[c];
    lo = glm::min(lo, centre - extent);
    hi = glm::max(hi, centre + extent);
  }
  return {lo, hi};
}

}  // namespace

std::vector<ReflectionProbe> probe_in_bounds(const Scene& scene) {
  if (scene.instances.empty()) return {};
  const auto [lo, hi] = world_bounds(scene);
  return {ReflectionProbe{(lo + hi) * 0.5, lo, hi}};
}

glm::dvec3 Scene::bounds_min() const { return world_bounds(*this).first; }
glm::dvec3 Scene::bounds_max() const { return world_bounds(*this).second; }

std::set<std::string> Scene::features() const {
  std::set<std::string> f;
  for (const Instance& instance : instances) {
    const Material& m = materials.at(material_of(instance));
    if (instance.moving) f.insert("moving_geometry");
    if (m.decal) {
      f.insert("mesh_decals");
      continue;  // drawn by decals.mesh alone: no geometry of the G-buffer passes
    }
    f.insert(m.alpha_mode == AlphaMode::mask ? "mask_geometry" : "opaque_geometry");
    if (m.emissive != glm::vec3(0.0f)) f.insert("emissive");
  }
  if (!decals.empty()) f.insert("projected_decals");
  if (!probes.empty()) f.insert("reflection_probes");
  for (const Light& l : lights) f.insert(l.type == LightType::directional ? "sun" : "local_lights");
  // Spot lights are the local lights with shadow maps (shadow.local_plan).
  for (const Light& l : lights)
    if (l.type == LightType::spot) f.insert("spot_lights");
  // The first directional light is the sun (frame.constants); its shadows need it above the horizon.
  for (const Light& l : lights)
    if (l.type == LightType::directional) {
      if (l.direction.y < 0.0f) f.insert("sun_above_horizon");
      break;
    }
  return f;
}

}  // namespace nightcap
