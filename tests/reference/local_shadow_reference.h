// A CPU reference for the spot lights' shadows (shadow.local_plan, shadow.local,
// shadow.local_moments and lighting.tiled's lookup), shared by the unit test and the benchmark:
// a pixel's surface point (from the depth, normal and camera view lighting.tiled read) is lit when
// the segment from it to the light meets none of the scene's opaque triangles (in double
// precision, shadow_reference.h's triangles). The pass's visibility is lighting.diffuse with
// the maps over lighting.diffuse of the same frame without them (shadow.local_plan.max_maps 0).
// Pixels closer than blur + 2 map texels (measured at the receiver) to an edge of the ray
// cast's shadow are set apart: a filtered map cannot place an edge closer.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <string>

#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/frame/gpu_types.h"
#include "passes/scene/scene.h"
#include "passes/scene/scene_kit.h"
#include "tests/reference/shadow_reference.h"

namespace nightcap::reference {

inline Light spot_light(const glm::dvec3& position, const glm::vec3& direction, float range) {
  Light l;
  l.type = LightType::spot;
  l.position = position;
  l.direction = glm::normalize(direction);
  l.intensity = 400.0f;
  l.range = range;
  l.inner_cone = 0.5f;
  l.outer_cone = 0.8f;
  return l;
}

// A ground plane (its top at y = 0) with boxes (centre, half size), lit by `lights`.
inline Scene boxes_scene(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& boxes, std::vector<Light> lights,
                         const glm::dvec3& eye, const glm::dvec3& target) {
  Scene scene;
  scene.source = "local shadow reference";
  scene_kit::Builder build(scene);
  const uint32_t grey = build.material(scene_kit::plain("ground", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
  build.place(build.box(glm::vec3(40.0f, 0.05f, 40.0f), grey, 1.0f, true, true), {0.0, -0.05, 0.0});
  for (const auto& [centre, half] : boxes) build.place(build.box(glm::vec3(half), grey, 1.0f, true, true), centre);
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  camera.world = glm::inverse(glm::lookAt(eye, target, glm::dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  scene.lights = std::move(lights);
  return scene;
}

// One spot light over two boxes, one on the ground and one floating: the agreement scene.
inline const glm::dvec3 kSpotBoxesEye(7.0, 7.0, 9.0);
inline Scene spot_boxes_scene() {
  return boxes_scene({{{0.0, 1.0, 0.0}, {0.8, 1.0, 0.8}}, {{-1.5, 2.5, 1.5}, {1.0, 0.05, 1.0}}},
                     {spot_light({0.6, 6.0, 0.4}, {-0.1f, -1.0f, 0.05f}, 15.0f)}, kSpotBoxesEye, {0.0, 0.0, 0.0});
}

// Two stacked occluders under a spot light 8 m up: B (4 m up) over A (`lower_height` up), A
// reaching out past B's side. Under B's side a filter over the map mixes B's and A's depths,
// and the ground behind both gets light through the variance: accuracy.md's leak case. The
// nearer A is to the ground, the more the ground leaks (Chebyshev's bound grows as the receiver
// nears the mean of the depths).
inline const glm::dvec3 kStackedEye(9.0, 10.0, 9.0);
inline Scene stacked_occluders_scene(double lower_height = 2.0) {
  return boxes_scene({{{0.0, 4.0, 0.0}, {1.5, 0.05, 1.5}}, {{2.0, lower_height, 0.0}, {1.5, 0.05, 1.5}}},
                     {spot_light({0.0, 8.0, 0.0}, {0.0f, -1.0f, 0.0f}, 20.0f)}, kStackedEye, {1.5, 0.0, 0.0});
}

// Whether a triangle meets the segment from `from` to `to` (both ends excluded).
inline bool segment_blocked(const ShadowTriangles& scene, const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 direction = to - from;
  for (const auto& t : scene.list) {
    const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
    const glm::dvec3 p = glm::cross(direction, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-14) continue;
    const glm::dvec3 s = from - t[0];
    const double u = glm::dot(s, p) / det;
    if (u < 0 || u > 1) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(direction, q) / det;
    if (v < 0 || u + v > 1) continue;
    const double at = glm::dot(e2, q) / det;
    if (at > 0 && at < 1 - 1e-9) return true;
  }
  return false;
}

struct LocalComparison {
  size_t compared = 0, agreed = 0, ray_shadowed = 0, near_edge = 0;
  double error_sum = 0.0;
  double umbra_max = 0.0, umbra_sum = 0.0;  // the pass's visibility at the ray-shadowed pixels compared
  double share() const { return compared ? double(agreed) / compared : 0.0; }
  double mean_error() const { return compared ? error_sum / compared : 0.0; }
  double umbra_mean() const { return ray_shadowed ? umbra_sum / ray_shadowed : 0.0; }
};

// `shadowed` and `open`: lighting.tiled's inputs and outputs with and without the maps, for a
// scene whose only light is scene.lights[0], a spot, seen from `eye` (world). Every `stride`-th
// pixel the light reaches (unshadowed diffuse above 2% of its largest) is compared.
inline LocalComparison compare_local_shadow(const Scene& scene, const glm::dvec3& eye,
                                            const std::map<std::string, IsolatedInput>& inputs,
                                            const IsolatedInput& shadowed, const IsolatedInput& open, double resolution,
                                            double blur, uint32_t stride) {
  auto texel = [](const IsolatedInput& image, uint64_t index) {
    std::array<float, 4> out{};
    decode_texel(*format_info(image.desc.format), 0, *image.bytes, index, out.data());
    return out;
  };
  const uint32_t width = shadowed.desc.extent.width, height = shadowed.desc.extent.height;
  GpuView camera{};
  std::memcpy(&camera, inputs.at("frame.views").bytes->data(), sizeof(camera));
  const IsolatedInput &depth = inputs.at("scene.depth"), &normal = inputs.at("gbuffer.normal");
  const Light& light = scene.lights.at(0);
  const glm::dvec3 origin = light.position - eye, axis = glm::normalize(glm::dvec3(light.direction));
  const ShadowTriangles triangles(scene, eye);
  double brightest = 0.0;
  for (uint64_t i = 0; i < uint64_t(width) * height; ++i) brightest = std::max(brightest, double(texel(open, i)[0]));
  LocalComparison c;
  for (uint32_t y = stride / 2; y < height; y += stride)
    for (uint32_t x = stride / 2; x < width; x += stride) {
      const uint64_t i = uint64_t(y) * width + x;
      const double z = texel(depth, i)[0], open_diffuse = texel(open, i)[0];
      if (z <= 0 || open_diffuse < 0.02 * brightest) continue;
      const double ndc_x = (x + 0.5) / width * 2 - 1, ndc_y = (y + 0.5) / height * 2 - 1;
      const glm::dvec4 h = glm::dmat4(camera.inverse_view_projection) * glm::dvec4(ndc_x, ndc_y, z, 1.0);
      const glm::dvec3 p = glm::dvec3(h) / h.w;
      const auto nt = texel(normal, i);
      const glm::dvec3 n = glm::normalize(glm::dvec3(nt[0], nt[1], nt[2]) * 2.0 - 1.0);
      const double view_depth = double(camera.projection_params.x) / z;
      // Off the surface by 2 mm + 10⁻⁴ of the view depth, as shadow_reference.h's sun rays.
      auto ray_lit = [&](const glm::dvec3& at) {
        return !segment_blocked(triangles, at + n * (2e-3 + 1e-4 * view_depth), origin);
      };
      const bool ray = ray_lit(p);
      // A map texel's side at the receiver: the map's half-angle is the outer cone's.
      const double along = std::max(glm::dot(p - origin, axis), 1e-3);
      const double texel_metres = 2.0 * along * std::tan(double(light.outer_cone)) / resolution;
      const glm::dvec3 u =
          glm::normalize(glm::cross(n, std::abs(n.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
      const glm::dvec3 v = glm::cross(n, u);
      bool edge = false;
      for (int k = 0; k < 8 && !edge; ++k) {
        const double angle = k * 0.7853981633974483;
        edge = ray_lit(p + (u * std::cos(angle) + v * std::sin(angle)) * ((blur + 2.0) * texel_metres)) != ray;
      }
      if (edge) {
        ++c.near_edge;
        continue;
      }
      const double visibility = std::clamp(texel(shadowed, i)[0] / open_diffuse, 0.0, 1.0);
      ++c.compared;
      c.agreed += (visibility >= 0.5) == ray;
      c.error_sum += std::abs(visibility - (ray ? 1.0 : 0.0));
      if (!ray) {
        ++c.ray_shadowed;
        c.umbra_max = std::max(c.umbra_max, visibility);
        c.umbra_sum += visibility;
      }
    }
  return c;
}

}  // namespace nightcap::reference
