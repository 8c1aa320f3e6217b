// Half-resolution inputs of the ambient-occlusion passes ray-cast on the CPU from planes and
// spheres: each half texel's depth (depth.half) and normal (normals.half) where the ray through its
// footprint's centre meets the nearest of them, as ao.gtao places the texel, and the world point
// it hit.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "passes/core/format.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/view.h"

namespace nightcap::test {

struct Plane {
  glm::dvec3 normal;      // unit
  double offset;          // the plane: dot(normal, p) = offset
  double top = INFINITY;  // nothing of it above this height
};

struct Sphere {
  glm::dvec3 centre;
  double radius;
};

// A half-resolution frame of planes and spheres seen from `eye`, looking along `forward`.
struct Synthetic {
  uint32_t width, height;  // the output (full) size
  GpuView view{};
  glm::dvec3 eye{0.0};
  std::vector<uint8_t> depth, normals;          // depth.half (R16F) and normals.half (RGBA8)
  std::vector<std::optional<glm::dvec3>> hits;  // world point of each half texel, if any
  uint32_t half_width() const { return (width + 1) / 2; }
  uint32_t half_height() const { return (height + 1) / 2; }
};

inline Synthetic cast(uint32_t width, uint32_t height, glm::dvec3 eye, glm::dvec3 forward,
                      const std::vector<Plane>& planes, const std::vector<Sphere>& spheres = {}) {
  Synthetic s;
  s.width = width;
  s.height = height;
  s.eye = eye;
  forward = glm::normalize(forward);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
  const glm::dvec3 up = glm::cross(right, forward);
  ViewPlacement placement;
  placement.orientation = glm::dmat3(right, up, -forward);
  placement.yfov = glm::radians(60.0);
  placement.znear = 0.1;
  placement.width = width;
  placement.height = height;
  s.view = perspective_view(placement);  // eye at the origin: positions relative to the camera
  const double tan_half = std::tan(placement.yfov / 2), aspect = double(width) / height;
  for (uint32_t y = 0; y < s.half_height(); ++y)
    for (uint32_t x = 0; x < s.half_width(); ++x) {
      // The footprint's centre, as ao.gtao places the texel.
      const double cx = (2.0 * x + std::min(2 * x + 1, width - 1) + 1) * 0.5;
      const double cy = (2.0 * y + std::min(2 * y + 1, height - 1) + 1) * 0.5;
      const double ndc_x = cx / width * 2 - 1, ndc_y = cy / height * 2 - 1;
      const glm::dvec3 ray = glm::normalize(forward + right * (ndc_x * tan_half * aspect) - up * (ndc_y * tan_half));
      double nearest = INFINITY;
      glm::dvec3 normal(0.0);
      for (const Plane& p : planes) {
        const double facing = glm::dot(p.normal, ray);
        if (std::abs(facing) < 1e-9) continue;
        const double t = (p.offset - glm::dot(p.normal, eye)) / facing;
        if (t > 0 && t < nearest && facing < 0 && (eye + ray * t).y <= p.top) {
          nearest = t;
          normal = p.normal;
        }
      }
      for (const Sphere& sphere : spheres) {
        // |eye + t·ray − centre|² = radius²: the nearer root, where the ray enters.
        const glm::dvec3 from_centre = eye - sphere.centre;
        const double b = glm::dot(ray, from_centre);
        const double discriminant = b * b - glm::dot(from_centre, from_centre) + sphere.radius * sphere.radius;
        if (discriminant < 0) continue;
        const double t = -b - std::sqrt(discriminant);
        if (t > 0 && t < nearest) {
          nearest = t;
          normal = glm::normalize(eye + ray * t - sphere.centre);
        }
      }
      const bool hit = std::isfinite(nearest);
      s.hits.push_back(hit ? std::optional(eye + ray * nearest) : std::nullopt);
      const float metres = hit ? float(std::min(nearest * glm::dot(ray, forward), 65504.0)) : 65504.0f;
      const uint16_t h = float_to_half(metres);
      s.depth.insert(s.depth.end(), {uint8_t(h & 0xff), uint8_t(h >> 8)});
      for (int c = 0; c < 3; ++c) s.normals.push_back(hit ? uint8_t(std::lround((normal[c] * 0.5 + 0.5) * 255)) : 128);
      s.normals.push_back(128);  // roughness, unread
    }
  return s;
}

// The vector an RGBA8 texel stores as 0.5·v + 0.5 (normals.half, ao.raw, ao.bent), texel `texel`.
inline glm::dvec3 decoded(const std::vector<uint8_t>& codes, size_t texel) {
  return glm::dvec3(codes[texel * 4], codes[texel * 4 + 1], codes[texel * 4 + 2]) / 255.0 * 2.0 - 1.0;
}

inline double degrees_between(glm::dvec3 a, glm::dvec3 b) {
  return glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)));
}

}  // namespace nightcap::test
