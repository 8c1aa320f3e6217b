// What the built-in scenes (city.cpp's block, map.cpp's map) are made of: a seeded random
// source whose sequence is the same on every platform, a builder of shared box meshes and
// instances, and the facade, plain and neon materials.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <random>
#include <string>
#include <vector>

#include "passes/scene/scene.h"

namespace nightcap::scene_kit {

class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}
  double uniform() { return double(engine_() >> 8) * (1.0 / 16777216.0); }
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  uint32_t below(uint32_t n) { return uint32_t(uniform() * n) % n; }

 private:
  std::mt19937 engine_;
};

// Boxes in local coordinates around their centre; UVs in metres × uv_scale so textures keep
// their size on every face.
class Builder {
 public:
  explicit Builder(Scene& scene) : scene_(scene) {}
  Scene& scene() { return scene_; }

  uint32_t box(glm::vec3 half, uint32_t material, float uv_scale, bool with_top = true, bool with_bottom = false) {
    begin(material);
    add_box(glm::vec3(0.0f), half, uv_scale, with_top, with_bottom);
    return end();
  }

  // A primitive of several boxes: begin, add_box…, end (which returns its index and sets its
  // bounds around every box).
  void begin(uint32_t material) {
    open_ = Primitive{};
    open_.first_index = uint32_t(scene_.indices.size());
    open_.vertex_offset = int32_t(scene_.vertices.size());
    open_.material = material;
    open_.bounds_min = glm::vec3(INFINITY);
    open_.bounds_max = glm::vec3(-INFINITY);
  }

  void add_box(glm::vec3 centre, glm::vec3 half, float uv_scale, bool with_top = true, bool with_bottom = false) {
    open_.bounds_min = glm::min(open_.bounds_min, centre - half);
    open_.bounds_max = glm::max(open_.bounds_max, centre + half);
    const uint32_t base_vertex = uint32_t(scene_.vertices.size()) - uint32_t(open_.vertex_offset);
    uint32_t base = base_vertex;
    for (int axis = 0; axis < 3; ++axis)
      for (int sign : {-1, 1}) {
        if (axis == 1 && sign > 0 && !with_top) continue;
        if (axis == 1 && sign < 0 && !with_bottom) continue;
        glm::vec3 n(0.0f);
        n[axis] = float(sign);
        // Two in-plane axes chosen so (u × v) = n: counter-clockwise seen from outside.
        const int ua = axis == 1 ? 0 : (axis == 0 ? 2 : 0);
        const int va = axis == 1 ? 2 : 1;
        glm::vec3 u(0.0f), v(0.0f);
        u[ua] = 1.0f;
        v[va] = 1.0f;
        if (glm::dot(glm::cross(u, v), n) < 0) u = -u;
        const glm::vec3 face_centre = n * half;
        const float hu = glm::dot(glm::abs(u), half), hv = glm::dot(glm::abs(v), half);
        for (int corner = 0; corner < 4; ++corner) {
          const float su = corner == 1 || corner == 2 ? 1.0f : -1.0f, sv = corner >= 2 ? 1.0f : -1.0f;
          const glm::vec3 position = centre + face_centre + u * (su * hu) + v * (sv * hv);
          Vertex vertex{};
          for (int k = 0; k < 3; ++k) {
            vertex.position[k] = position[k];
            vertex.normal[k] = n[k];
            vertex.tangent[k] = u[k];
          }
          vertex.tangent[3] = 1.0f;
          // Texture v grows downward in glTF: flip so windows stand upright. Facades keep their
          // texture in place across boxes: u follows the face, v the height above the base.
          vertex.uv0[0] = (su * hu + hu) * uv_scale;
          vertex.uv0[1] = (hv - sv * hv) * uv_scale;
          vertex.uv1[0] = vertex.uv0[0];
          vertex.uv1[1] = vertex.uv0[1];
          for (float& c : vertex.color) c = 1.0f;
          scene_.vertices.push_back(vertex);
        }
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) scene_.indices.push_back(base + i);
        base += 4;
      }
  }

  uint32_t end() {
    open_.index_count = uint32_t(scene_.indices.size()) - open_.first_index;
    scene_.primitives.push_back(open_);
    return uint32_t(scene_.primitives.size() - 1);
  }

  Instance& place(uint32_t primitive, glm::dvec3 centre, double yaw = 0.0) {
    Instance instance;
    instance.world = glm::rotate(glm::translate(glm::dmat4(1.0), centre), yaw, glm::dvec3(0, 1, 0));
    instance.primitive = primitive;
    scene_.instances.push_back(instance);
    return scene_.instances.back();
  }

  uint32_t material(Material m) {
    scene_.materials.push_back(std::move(m));
    return uint32_t(scene_.materials.size() - 1);
  }

 private:
  Scene& scene_;
  Primitive open_;
};

// Three facade materials, each with its own pair of 256² window textures (4×4 windows: concrete
// and dark glass, a random share of the windows lit in warm or cool tones), more windows lit in
// each; drawn from `random` in a fixed order.
std::vector<uint32_t> facade_materials(Random& random, Builder& build);

Material plain(const std::string& name, glm::vec3 colour, float metallic, float roughness, uint8_t stencil_class);

extern const std::array<glm::vec3, 5> kNeon;

// The lights both built-in scenes use: a neon tube along a sign, a sodium street lamp, the moon.
Light neon_tube(const glm::dvec3& start, const glm::dvec3& end, const glm::vec3& colour, float range);
Light street_lamp(const glm::dvec3& position, float range);
Light moon();

}  // namespace nightcap::scene_kit
