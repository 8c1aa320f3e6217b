// A CPU reference for the sun's shadow (shadow.cull, shadow.cascades, shadow.sun_resolve),
// shared by the unit test and the benchmark, written apart from the passes: each sampled pixel's
// surface point (from the depth and camera shadow.sun_resolve read) is lit when a ray from it
// toward the sun, in double precision, meets none of the scene's opaque triangles (brute force,
// at the level of detail the view draws). Pixels closer than 2 cascade texels, measured across
// the sun's rays, to an edge of the ray cast's shadow are set apart: a shadow map cannot place
// an edge closer than its texels (accuracy.md counts agreement away from edges).
#pragma once

#include <array>
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/frame/gpu_types.h"
#include "passes/scene/scene.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap::reference {

// The scene's opaque triangles, camera-relative (the eye subtracted in double), at time 0, at the
// level of detail the view draws (by the distance from the eye to the finest level's box centre).
struct ShadowTriangles {
  std::vector<std::array<glm::dvec3, 3>> list;

  ShadowTriangles(const Scene& scene, const glm::dvec3& eye) {
    for (const Instance& instance : scene.instances) {
      const Material& m = scene.materials.at(scene.material_of(instance));
      if (m.alpha_mode != AlphaMode::opaque || m.decal) continue;
      const Primitive* p = &scene.primitives.at(instance.primitive);
      const glm::dvec3 centre(glm::dvec3(p->bounds_min + p->bounds_max) * 0.5);
      const double distance = glm::length(glm::dvec3(instance.world * glm::dvec4(centre, 1.0)) - eye);
      while (p->coarser >= 0 && distance > p->lod_distance) p = &scene.primitives.at(p->coarser);
      if (distance > p->draw_distance) continue;
      for (uint32_t t = 0; t + 2 < p->index_count; t += 3) {
        std::array<glm::dvec3, 3> tri;
        for (int k = 0; k < 3; ++k) {
          const Vertex& v = scene.vertices.at(scene.indices.at(p->first_index + t + k) + p->vertex_offset);
          tri[k] = glm::dvec3(instance.world * glm::dvec4(v.position[0], v.position[1], v.position[2], 1.0)) - eye;
        }
        list.push_back(tri);
      }
    }
  }

  // Möller–Trumbore, both faces: whether the ray meets a triangle ahead of its origin.
  bool blocked(const glm::dvec3& origin, const glm::dvec3& direction) const {
    for (const auto& t : list) {
      const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
      const glm::dvec3 p = glm::cross(direction, e2);
      const double det = glm::dot(e1, p);
      if (std::abs(det) < 1e-14) continue;
      const glm::dvec3 s = origin - t[0];
      const double u = glm::dot(s, p) / det;
      if (u < 0 || u > 1) continue;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(direction, q) / det;
      if (v < 0 || u + v > 1) continue;
      if (glm::dot(e2, q) / det > 0) return true;
    }
    return false;
  }

  // Whether the surface point `p` (normal n, view depth d) sees the sun (unit `to_sun`): the ray
  // starts 2 mm + 10⁻⁴·d off the surface, so the float depth's rounding does not hit the surface.
  bool lit(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& to_sun, double d) const {
    return !blocked(p + n * (2e-3 + 1e-4 * d), to_sun);
  }
};

// What shadow.sun_resolve read and wrote, decoded.
struct ShadowView {
  uint32_t width = 0, height = 0;
  GpuView camera{};
  GpuShadowCascades cascades{};
  IsolatedInput depth, normal, sun;

  struct Surface {
    glm::dvec3 position, normal;  // camera-relative
    double view_depth;
  };

  ShadowView(const std::map<std::string, IsolatedInput>& inputs, const IsolatedInput& sun_output)
      : depth(inputs.at("scene.depth")), normal(inputs.at("gbuffer.normal")), sun(sun_output) {
    width = sun.desc.extent.width;
    height = sun.desc.extent.height;
    std::memcpy(&camera, inputs.at("frame.views").bytes->data(), sizeof(camera));
    std::memcpy(&cascades, inputs.at("shadow.cascade_data").bytes->data(), sizeof(cascades));
  }

  static std::array<float, 4> texel(const IsolatedInput& image, uint64_t index) {
    std::array<float, 4> out{};
    decode_texel(*format_info(image.desc.format), 0, *image.bytes, index, out.data());
    return out;
  }
  double visibility(uint32_t x, uint32_t y) const { return texel(sun, uint64_t(y) * width + x)[0]; }
  // The pixel's surface as the depth and normal hold it; none for sky.
  std::optional<Surface> surface(uint32_t x, uint32_t y) const {
    const uint64_t i = uint64_t(y) * width + x;
    const double z = texel(depth, i)[0];
    if (z <= 0) return std::nullopt;
    const double nx = (x + 0.5) / width * 2 - 1, ny = (y + 0.5) / height * 2 - 1;
    const glm::dvec4 p = glm::dmat4(camera.inverse_view_projection) * glm::dvec4(nx, ny, z, 1.0);
    const auto n = texel(normal, i);
    return Surface{glm::dvec3(p) / p.w, glm::normalize(glm::dvec3(n[0], n[1], n[2]) * 2.0 - 1.0),
                   double(camera.projection_params.x) / z};
  }
  uint32_t cascade_of(double view_depth) const {
    uint32_t c = 0;
    for (uint32_t k = 0; k + 1 < kShadowCascades; ++k) c += view_depth > cascades.splits[k];
    return c;
  }
  glm::dvec3 to_sun() const { return -glm::normalize(glm::dvec3(glm::vec3(cascades.light_direction))); }
};

struct ShadowAgreement {
  size_t compared = 0, agreed = 0;  // away from the ray cast's shadow edges
  size_t near_edge = 0, near_edge_agreed = 0;
  size_t ray_shadowed = 0;  // of those compared
  std::string first_disagreement;
  double share() const { return compared ? double(agreed) / compared : 0.0; }
  double share_everywhere() const {
    return compared + near_edge ? double(agreed + near_edge_agreed) / double(compared + near_edge) : 0.0;
  }
};

// Every `stride`-th pixel of every `stride`-th row that faces the sun (n·l > 0.1: others get no
// sunlight whatever the shadow says) and lies before the last split: the pass's visibility
// (≥ 0.5 lit) against the ray cast.
inline ShadowAgreement shadow_agreement(const ShadowView& f, const ShadowTriangles& scene, uint32_t stride) {
  ShadowAgreement a;
  const glm::dvec3 l = f.to_sun();
  for (uint32_t y = stride / 2; y < f.height; y += stride)
    for (uint32_t x = stride / 2; x < f.width; x += stride) {
      const auto s = f.surface(x, y);
      if (!s || s->view_depth > f.cascades.splits[3] || glm::dot(s->normal, l) <= 0.1) continue;
      const bool lit = scene.lit(s->position, s->normal, l, s->view_depth);
      // Near an edge when any of 8 points of the surface's plane, 2 texels from the pixel's
      // across the sun's rays, gets the other answer.
      const double texel = f.cascades.texel_metres[f.cascade_of(s->view_depth)];
      const glm::dvec3 u = glm::normalize(
          glm::cross(s->normal, std::abs(s->normal.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
      const glm::dvec3 v = glm::cross(s->normal, u);
      bool edge = false;
      for (int k = 0; k < 8 && !edge; ++k) {
        const double angle = k * 0.7853981633974483;
        const glm::dvec3 w = u * std::cos(angle) + v * std::sin(angle);
        const double across = glm::length(w - glm::dot(w, l) * l);
        edge = scene.lit(s->position + w * (2.0 * texel / std::max(across, 0.1)), s->normal, l, s->view_depth) != lit;
      }
      const bool agrees = (f.visibility(x, y) >= 0.5) == lit;
      if (edge) {
        ++a.near_edge;
        a.near_edge_agreed += agrees;
        continue;
      }
      ++a.compared;
      a.ray_shadowed += !lit;
      a.agreed += agrees;
      if (!agrees && a.first_disagreement.empty())
        a.first_disagreement = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": ray cast " +
                               (lit ? "lit" : "shadowed") + ", visibility " + std::to_string(f.visibility(x, y));
    }
  return a;
}

}  // namespace nightcap::reference
