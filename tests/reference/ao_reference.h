// Monte Carlo ambient occlusion traced through a frame's depth buffer as a height field, the
// reference of the AO chain (tests/e2e/ao_reference_test.cpp, the benchmark's `ao` section).
// At half texels whose search radius lies on screen, from the point and normal the chain starts
// from (depth.half and normals.half at the footprint's centre): 512 cosine-weighted directions
// (16 × 32 strata), each marched in 64 steps out to the radius through depth.linear (full
// resolution; 1/depth interpolated between the four texels around a position where it runs on
// across them as over a plane, untwisted and without a step that stands out from the texels
// beyond, the nearest texel elsewhere).
// The thickness rule is ao.gtao's: where the ray passes behind the depth buffer by at most
// `thickness` (in depth), the occluder is the surface seen there, and it counts by that surface's
// distance d from the point, the ray being visible by 1 − clamp((radius − d)/(falloff · radius),
// 0, 1) at the first such surface within the radius (a surface farther away, in front of the
// point, hides nothing behind it; farther behind a surface than `thickness`, the ray goes on);
// nothing within a half texel (2 pixels) of the point on screen occludes it, as ao.gtao's nearest
// sample is a half texel away; a ray that leaves the screen is visible. Rays cast at the scene's
// triangles (SceneRays) measure what the depth buffer cannot show.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "passes/frame/gpu_types.h"
#include "passes/scene/scene.h"

namespace nightcap::reference {

// What the reference reads of one frame: the camera's view, depth.linear (one float a texel),
// depth.half (one), normals.half (four, 0…1) and ao.gtao's radius, falloff and thickness.
struct AoFrame {
  GpuView view{};
  uint32_t width = 0, height = 0;
  std::vector<float> depth, half_depth, half_normals;
  double radius = 0, falloff = 0, thickness = INFINITY;

  // ao.gtao's `thickness` as the depth of its slabs: 0 means solid.
  static double slab_depth(double thickness_param) { return thickness_param > 0 ? thickness_param : INFINITY; }

  uint32_t half_width() const { return (width + 1) / 2; }
  uint32_t half_height() const { return (height + 1) / 2; }

  glm::dvec3 view_point(glm::dvec2 pixel, double metres) const {
    const glm::dvec2 ndc = pixel / glm::dvec2(width, height) * 2.0 - 1.0;
    return {metres * (ndc.x + view.projection[2][0]) / view.projection[0][0],
            metres * (ndc.y + view.projection[2][1]) / view.projection[1][1], -metres};
  }
  glm::dvec2 pixel_of(glm::dvec3 p) const {
    const glm::dvec2 ndc(-(view.projection[0][0] * p.x + view.projection[2][0] * p.z) / p.z,
                         -(view.projection[1][1] * p.y + view.projection[2][1] * p.z) / p.z);
    return (ndc + 1.0) * 0.5 * glm::dvec2(width, height);
  }
  // depth.linear at full-resolution position `pixel`.
  double depth_at(glm::dvec2 pixel) const {
    const int w = int(width), h = int(height);
    const glm::dvec2 below = pixel - 0.5;
    const int x0 = std::clamp(int(std::floor(below.x)), 0, w - 2), y0 = std::clamp(int(std::floor(below.y)), 0, h - 2);
    const double fx = std::clamp(below.x - x0, 0.0, 1.0), fy = std::clamp(below.y - y0, 0.0, 1.0);
    const double i00 = inverse_depth({x0, y0}), i10 = inverse_depth({x0 + 1, y0});
    const double i01 = inverse_depth({x0, y0 + 1}), i11 = inverse_depth({x0 + 1, y0 + 1});
    const double largest = std::max({i00, i10, i01, i11}), smallest = std::min({i00, i10, i01, i11});
    const bool one_plane = std::abs(i00 + i11 - i10 - i01) <= 0.01 * largest && largest <= 2 * smallest &&
                           smallest > 0 && continues({x0, y0}, {1, 0}) && continues({x0, y0 + 1}, {1, 0}) &&
                           continues({x0, y0}, {0, 1}) && continues({x0 + 1, y0}, {0, 1});
    if (one_plane) return 1.0 / ((1 - fy) * ((1 - fx) * i00 + fx * i10) + fy * ((1 - fx) * i01 + fx * i11));
    const int nx = std::clamp(int(pixel.x), 0, w - 1), ny = std::clamp(int(pixel.y), 0, h - 1);
    return depth[size_t(ny) * w + nx];
  }

 private:
  double inverse_depth(glm::ivec2 texel) const { return 1.0 / depth[size_t(texel.y) * width + texel.x]; }
  bool inside(glm::ivec2 texel) const {
    return texel.x >= 0 && texel.y >= 0 && texel.x < int(width) && texel.y < int(height);
  }
  // Whether 1/depth runs on across the gap from `texel` to texel + `step` as it does over a plane,
  // where it changes by the same amount from texel to texel, rather than jumping at a silhouette:
  // the change across the gap departs from the changes just before and after it (where the image
  // has them) by at most a quarter of the largest. A silhouette parallel to the gap keeps the four
  // texels around a position untwisted, and interpolating across it would raise a wall between
  // the two surfaces that occludes what lies behind the nearer one.
  bool continues(glm::ivec2 texel, glm::ivec2 step) const {
    const glm::ivec2 next = texel + step;
    const double across = inverse_depth(next) - inverse_depth(texel);
    double largest = std::abs(across), departure = 0;
    for (const auto& [from, to] : {std::pair{texel - step, texel}, std::pair{next, next + step}}) {
      if (!inside(from) || !inside(to)) continue;
      const double change = inverse_depth(to) - inverse_depth(from);
      largest = std::max(largest, std::abs(change));
      departure = std::max(departure, std::abs(across - change));
    }
    return departure <= 0.25 * largest + 1e-6 * inverse_depth(texel);
  }
};

// The reference at one half texel: its visibility and mean unoccluded direction (world space),
// from `point` (view space) on a surface of normal `normal` (world space).
struct AoSample {
  uint32_t half_x = 0, half_y = 0;
  double visibility = 1;
  glm::dvec3 direction{0.0};
  glm::dvec3 point{0.0}, normal{0.0};
};

// Over the reference's 512 directions about unit normal `n` (cosine-weighted, one jittered within
// each of 16 rings × 32 sectors, in a fixed order), the mean of `visibility_of(direction)` and the
// mean unoccluded direction, the directions weighted by it (unnormalised).
struct Hemisphere {
  double visibility = 0;
  glm::dvec3 direction{0.0};
};
template <class VisibilityOf>
Hemisphere over_hemisphere(glm::dvec3 n, std::mt19937& random, VisibilityOf&& visibility_of) {
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 tangent = glm::normalize(glm::cross(helper, n)), bitangent = glm::cross(n, tangent);
  std::uniform_real_distribution<double> jitter(0.0, 1.0);
  constexpr int kRings = 16, kSectors = 32;
  Hemisphere h;
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSectors; ++j) {
      const double u = (i + jitter(random)) / kRings, phi = 2 * M_PI * (j + jitter(random)) / kSectors;
      const double s = std::sqrt(u);
      const glm::dvec3 ray = tangent * (s * std::cos(phi)) + bitangent * (s * std::sin(phi)) + n * std::sqrt(1 - u);
      const double visibility = visibility_of(ray);
      h.visibility += visibility;
      h.direction += visibility * ray;
    }
  h.visibility /= kRings * kSectors;
  return h;
}

inline AoSample trace_ao(const AoFrame& f, uint32_t half_x, uint32_t half_y, glm::dvec3 point, glm::dvec3 normal_world,
                         std::mt19937& random) {
  const glm::dmat3 view_from_world(glm::dmat4(f.view.view));
  const glm::dvec2 centre = f.pixel_of(point);
  const Hemisphere h = over_hemisphere(glm::normalize(view_from_world * normal_world), random, [&](glm::dvec3 ray) {
    constexpr int kSteps = 64;
    for (int k = 1; k <= kSteps; ++k) {
      const glm::dvec3 q = point + ray * (f.radius * k / kSteps);
      if (q.z >= -1e-3) break;  // behind the camera
      const glm::dvec2 pixel = f.pixel_of(q);
      if (pixel.x < 0 || pixel.y < 0 || pixel.x >= f.width || pixel.y >= f.height) break;
      // Within one half texel of the point on screen nothing occludes it: ao.gtao's nearest
      // sample is a half texel away, and the nearest texel's depth there is a step.
      if (glm::length(pixel - centre) < 2.0) continue;
      const double surface = f.depth_at(pixel);
      if (-q.z <= surface * (1 + 1e-4)) continue;
      if (-q.z > surface + f.thickness) continue;  // behind the surface's slab: open
      // Behind the depth buffer: the occluder is the surface seen there, weighted by its distance;
      // one beyond the radius hides nothing, and the ray goes on.
      const double weight =
          std::clamp((f.radius - glm::length(f.view_point(pixel, surface) - point)) / (f.falloff * f.radius), 0.0, 1.0);
      if (weight > 0.0) return 1.0 - weight;
    }
    return 1.0;
  });
  return {half_x, half_y, h.visibility, glm::transpose(view_from_world) * h.direction, point, normal_world};
}

// The reference at every `stride`-th half texel (from 1, 1) where something was drawn and the
// radius lies on screen (with 2 pixels to spare), in a fixed order and with fixed noise.
inline std::vector<AoSample> monte_carlo_ao(const AoFrame& f, uint32_t stride = 4) {
  std::vector<AoSample> samples;
  std::mt19937 random(1);
  const double pixels_at_one_metre = 0.5 * f.height * std::abs(f.view.projection[1][1]);
  for (uint32_t y = 1; y < f.half_height(); y += stride)
    for (uint32_t x = 1; x < f.half_width(); x += stride) {
      const size_t i = size_t(y) * f.half_width() + x;
      const double metres = f.half_depth[i];
      const glm::dvec3 normal =
          glm::dvec3(f.half_normals[i * 4], f.half_normals[i * 4 + 1], f.half_normals[i * 4 + 2]) * 2.0 - 1.0;
      if (!(metres > 0 && metres < 65504) || glm::dot(normal, normal) < 1e-4) continue;
      const glm::dvec2 centre((2.0 * x + std::min(2 * x + 1, f.width - 1) + 1) * 0.5,
                              (2.0 * y + std::min(2 * y + 1, f.height - 1) + 1) * 0.5);
      const double reach = f.radius * pixels_at_one_metre / metres + 2;
      if (centre.x < reach || centre.y < reach || centre.x > f.width - reach || centre.y > f.height - reach) continue;
      samples.push_back(trace_ao(f, x, y, f.view_point(centre, metres), glm::normalize(normal), random));
    }
  return samples;
}

// The same directions cast at the scene's triangles instead (the finest level of detail of every
// instance, mask geometry solid): what a screen-space method cannot see, off screen and behind
// the depth buffer's first surface. Each sample's rays start at its point (camera-relative
// world, the view's orientation being the world's) lifted off its surface by 1 cm + 0.2% of its
// depth, the half-float depth's error, and see the triangles within the radius.
class SceneRays {
 public:
  // `eye`: the world position of the camera-relative origin (frame.constants' camera_world).
  SceneRays(Scene scene, glm::dvec3 eye) : scene_(std::move(scene)), eye_(eye) {
    for (const Instance& instance : scene_.instances) {
      const Primitive& p = scene_.primitives[instance.primitive];
      glm::dvec3 low(INFINITY), high(-INFINITY);
      for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 local(corner & 1 ? p.bounds_max.x : p.bounds_min.x,
                               corner & 2 ? p.bounds_max.y : p.bounds_min.y,
                               corner & 4 ? p.bounds_max.z : p.bounds_min.z);
        const glm::dvec3 world = glm::dvec3(instance.world * glm::dvec4(local, 1.0)) - eye;
        low = glm::min(low, world);
        high = glm::max(high, world);
      }
      bounds_.push_back({low, high});
    }
  }

  // The visibility and mean unoccluded direction at `sample`'s point, over the same strata.
  AoSample trace(const AoFrame& f, const AoSample& sample, std::mt19937& random) const {
    const glm::dmat3 world_from_view = glm::transpose(glm::dmat3(glm::dmat4(f.view.view)));
    const glm::dvec3 n = glm::normalize(sample.normal);
    const glm::dvec3 origin = world_from_view * sample.point + n * (0.01 + 0.002 * -sample.point.z);
    const std::vector<glm::dvec3> triangles = near(origin, f.radius);
    const Hemisphere h = over_hemisphere(n, random, [&](glm::dvec3 ray) {
      double nearest = f.radius;
      for (size_t t = 0; t < triangles.size(); t += 3)
        nearest = std::min(nearest, hit(origin, ray, triangles[t], triangles[t + 1], triangles[t + 2]));
      return 1.0 - std::clamp((f.radius - nearest) / (f.falloff * f.radius), 0.0, 1.0);
    });
    return {sample.half_x, sample.half_y, h.visibility, h.direction, sample.point, sample.normal};
  }

 private:
  // The corners (camera-relative) of every triangle whose bounds come within `radius` of `at`.
  std::vector<glm::dvec3> near(glm::dvec3 at, double radius) const {
    std::vector<glm::dvec3> corners;
    for (size_t k = 0; k < bounds_.size(); ++k) {
      if (glm::length(at - glm::clamp(at, bounds_[k].first, bounds_[k].second)) > radius) continue;
      const Instance& instance = scene_.instances[k];
      const Primitive& p = scene_.primitives[instance.primitive];
      for (uint32_t i = 0; i + 2 < p.index_count; i += 3) {
        glm::dvec3 c[3];
        for (int v = 0; v < 3; ++v) {
          const float* position =
              scene_.vertices[size_t(int64_t(scene_.indices[p.first_index + i + v]) + p.vertex_offset)].position;
          c[v] = glm::dvec3(instance.world * glm::dvec4(position[0], position[1], position[2], 1.0)) - eye_;
        }
        const glm::dvec3 low = glm::min(c[0], glm::min(c[1], c[2])), high = glm::max(c[0], glm::max(c[1], c[2]));
        if (glm::length(at - glm::clamp(at, low, high)) > radius) continue;
        corners.insert(corners.end(), c, c + 3);
      }
    }
    return corners;
  }
  // The distance along `ray` (unit) from `origin` to triangle abc, INFINITY when it misses
  // (Möller and Trumbore 1997); either side of the triangle counts.
  static double hit(glm::dvec3 origin, glm::dvec3 ray, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const glm::dvec3 ab = b - a, ac = c - a, p = glm::cross(ray, ac);
    const double det = glm::dot(ab, p);
    if (std::abs(det) < 1e-18) return INFINITY;
    const glm::dvec3 to_origin = origin - a;
    const double u = glm::dot(to_origin, p) / det;
    if (u < 0 || u > 1) return INFINITY;
    const glm::dvec3 q = glm::cross(to_origin, ab);
    const double v = glm::dot(ray, q) / det;
    if (v < 0 || u + v > 1) return INFINITY;
    const double t = glm::dot(ac, q) / det;
    return t > 0 ? t : INFINITY;
  }

  Scene scene_;
  glm::dvec3 eye_;
  std::vector<std::pair<glm::dvec3, glm::dvec3>> bounds_;  // each instance's, camera-relative
};

// How an ao_bent image (four floats a texel, 0…1) departs from the reference: |visibility error|
// and the bent normal's angle to the mean unoccluded direction (degrees) at each sample.
struct AoErrors {
  std::vector<double> visibility, degrees;

  static double mean(const std::vector<double>& v) {
    double sum = 0;
    for (double x : v) sum += x;
    return v.empty() ? 0 : sum / v.size();
  }
  static double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * v.size()))];
  }
};

inline AoErrors ao_errors(const AoFrame& f, const std::vector<AoSample>& samples, const std::vector<float>& bent) {
  AoErrors e;
  for (const AoSample& s : samples) {
    const size_t i = size_t(s.half_y) * f.half_width() + s.half_x;
    e.visibility.push_back(std::abs(bent[i * 4 + 3] - s.visibility));
    const glm::dvec3 b = glm::dvec3(bent[i * 4], bent[i * 4 + 1], bent[i * 4 + 2]) * 2.0 - 1.0;
    if (glm::length(s.direction) > 1e-6 && glm::length(b) > 0.1)
      e.degrees.push_back(
          glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(b), glm::normalize(s.direction)), -1.0, 1.0))));
  }
  return e;
}

}  // namespace nightcap::reference
