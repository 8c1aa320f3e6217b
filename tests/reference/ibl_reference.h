// CPU references for the sky's image-based light (passes/sky/cubemap, irradiance, specular and
// passes/lighting/dfg), shared by their unit tests and the benchmark. Double precision, written
// from the definitions rather than the shaders: cube faces by Vulkan's face-selection table
// (a direction's major axis picks the face), bilinear lookups within a face, the GGX-prefiltered
// radiance as the split sum defines it (Karis 2013) estimated from many samples of mip 0 with no
// mip selection, irradiance as the exact cosine-weighted sum over every texel, and spherical
// harmonics by their own projection.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <numbers>
#include <vector>

#include "passes/core/format.h"

namespace nightcap::reference {

using glm::dvec3;

// One level of a cube map, decoded: 6 faces of side × side texels, face-major, rows down.
struct CubeLevel {
  uint32_t side = 0;
  std::vector<dvec3> texels;
  const dvec3& at(uint32_t face, uint32_t x, uint32_t y) const { return texels[(size_t(face) * side + y) * side + x]; }
};

// Level `mip` of cube `cube` (layers 6·cube to 6·cube + 5) of a cube or cube-array image of
// `format` and `extent` stored as the capture lays it out.
inline CubeLevel cube_array_level(const std::vector<uint8_t>& bytes, VkFormat format, const ImageExtent& extent,
                                  uint32_t cube, uint32_t mip) {
  const FormatInfo f = *format_info(format);
  CubeLevel level;
  level.side = mip_size(extent.width, mip);
  level.texels.resize(size_t(level.side) * level.side * 6);
  const uint64_t offset = raw_subresource_offset(f, extent, 0, mip, 6 * cube);
  const std::span<const uint8_t> plane(bytes.data() + offset, bytes.size() - offset);
  for (size_t i = 0; i < level.texels.size(); ++i) {
    float t[4];
    decode_texel(f, 0, plane, i, t);
    level.texels[i] = dvec3(t[0], t[1], t[2]);
  }
  return level;
}

// Level `mip` of a 6-layer cube image of `format` stored as the capture lays it out.
inline CubeLevel cube_level(const std::vector<uint8_t>& bytes, VkFormat format, uint32_t side0, uint32_t mips,
                            uint32_t mip) {
  return cube_array_level(bytes, format, ImageExtent{side0, side0, 1, mips, 6}, 0, mip);
}

// Vulkan's cube map face selection: the face of the direction's major axis and (s, t) in [0, 1]².
inline void face_coordinates(const dvec3& d, uint32_t& face, double& s, double& t) {
  const dvec3 a = glm::abs(d);
  double sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x >= 0 ? 0 : 1;
    sc = d.x >= 0 ? -d.z : d.z;
    tc = -d.y;
    ma = a.x;
  } else if (a.y >= a.z) {
    face = d.y >= 0 ? 2 : 3;
    sc = d.x;
    tc = d.y >= 0 ? d.z : -d.z;
    ma = a.y;
  } else {
    face = d.z >= 0 ? 4 : 5;
    sc = d.z >= 0 ? d.x : -d.x;
    tc = -d.y;
    ma = a.z;
  }
  s = 0.5 * (sc / ma + 1.0);
  t = 0.5 * (tc / ma + 1.0);
}

// The unit direction through the centre of texel (x, y) of `face`, found by inverting
// face_coordinates: the major axis is the face's, the other two follow from (s, t).
// The point of `face`'s plane (at distance 1) at (sc, tc) in [-1, 1]², or beyond for a point past
// its edge.
inline dvec3 face_point(uint32_t face, double sc, double tc) {
  const std::array<dvec3, 6> d{dvec3(1, -tc, -sc), dvec3(-1, -tc, sc), dvec3(sc, 1, tc),
                               dvec3(sc, -1, -tc), dvec3(sc, -tc, 1),  dvec3(-sc, -tc, -1)};
  return d[face];
}

inline dvec3 texel_direction(uint32_t face, uint32_t x, uint32_t y, uint32_t side) {
  return glm::normalize(face_point(face, 2.0 * (x + 0.5) / side - 1.0, 2.0 * (y + 0.5) / side - 1.0));
}

// Bilinear as a seamless cube sampler reads it (Vulkan's cube maps always are): a texel beyond the
// face's edge is the one the adjacent face holds in the same direction (at a corner, one of the
// three a device may average).
inline dvec3 sample(const CubeLevel& level, const dvec3& direction) {
  uint32_t face;
  double s, t;
  face_coordinates(direction, face, s, t);
  const double side = level.side, x = s * side - 0.5, y = t * side - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
  const auto at = [&](double xi, double yi) {
    if (xi >= 0 && yi >= 0 && xi < side && yi < side) return level.at(face, uint32_t(xi), uint32_t(yi));
    uint32_t other;
    double os, ot;
    face_coordinates(face_point(face, 2.0 * (xi + 0.5) / side - 1.0, 2.0 * (yi + 0.5) / side - 1.0), other, os, ot);
    return level.at(other, uint32_t(std::clamp(std::floor(os * side), 0.0, side - 1)),
                    uint32_t(std::clamp(std::floor(ot * side), 0.0, side - 1)));
  };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

// The solid angle texel (x, y) of a face subtends: the face's projected area integrated in
// closed form over the texel's rectangle (at distance 1, ∫∫ (1 + u² + v²)^(-3/2)).
inline double texel_solid_angle(uint32_t x, uint32_t y, uint32_t side) {
  const auto area = [](double u, double v) { return std::atan2(u * v, std::sqrt(u * u + v * v + 1.0)); };
  const double u0 = 2.0 * x / side - 1.0, u1 = 2.0 * (x + 1.0) / side - 1.0;
  const double v0 = 2.0 * y / side - 1.0, v1 = 2.0 * (y + 1.0) / side - 1.0;
  return area(u0, v0) - area(u0, v1) - area(u1, v0) + area(u1, v1);
}

inline double radical_inverse(uint32_t i) {
  double result = 0, digit = 0.5;
  for (; i; i >>= 1, digit *= 0.5)
    if (i & 1u) result += digit;
  return result;
}

// GGX's split-sum prefilter at n = v = r and α = roughness²: Σ L(l) G1(l) / Σ G1(l) over `samples`
// half vectors distributed as D(h) n·h (a Hammersley set), L read bilinearly from `source`. G1,
// Smith's masking of l, is the height-correlated G2 at n = v, so that at normal incidence the
// split sum is the GGX integral (Karis 2013 weights by n·l instead).
inline dvec3 prefiltered(const CubeLevel& source, const dvec3& n, double roughness, uint32_t samples) {
  if (roughness == 0.0) return sample(source, n);
  const double a2 = std::pow(roughness, 4.0);
  const dvec3 up = std::abs(n.y) < 0.999 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
  const dvec3 tangent = glm::normalize(glm::cross(up, n)), bitangent = glm::cross(n, tangent);
  dvec3 sum(0.0);
  double weight = 0;
  for (uint32_t i = 0; i < samples; ++i) {
    const double xi = (i + 0.5) / samples, phi = 2.0 * std::numbers::pi * radical_inverse(i);
    const double cos_h = std::sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));
    const double sin_h = std::sqrt(std::max(1.0 - cos_h * cos_h, 0.0));
    const dvec3 h = tangent * (sin_h * std::cos(phi)) + bitangent * (sin_h * std::sin(phi)) + n * cos_h;
    const dvec3 l = 2.0 * glm::dot(n, h) * h - n;
    const double n_l = glm::dot(n, l);
    if (n_l <= 0) continue;
    const double tan2 = (1.0 - n_l * n_l) / (n_l * n_l), masking = 2.0 / (1.0 + std::sqrt(1.0 + a2 * tan2));
    sum += sample(source, l) * masking;
    weight += masking;
  }
  return sum / weight;
}

// Trilinear between mips as the sampler reads a prefiltered cube (`levels`, mip 0 first) at `lod`.
inline dvec3 sample_lod(const std::vector<CubeLevel>& levels, const dvec3& direction, double lod) {
  const double clamped = std::clamp(lod, 0.0, double(levels.size() - 1));
  const uint32_t below = uint32_t(std::floor(clamped)), above = std::min(below + 1, uint32_t(levels.size() - 1));
  return glm::mix(sample(levels[below], direction), sample(levels[above], direction), clamped - below);
}

// The GGX specular light reflected toward v by a surface of normal n under the cube's light, the
// integral the split sum approximates: ∫ L(l) D G₂ F / (4 n·v n·l) n·l dl with height-correlated
// Smith masking-shadowing and Schlick's Fresnel at f0, α = roughness², estimated from `samples`
// half vectors distributed as D(h) n·h (a Hammersley set; each weighs F V 4 (v·h)(n·l) / (n·h),
// V = G₂ / (4 n·l n·v)), L read bilinearly from `source`.
inline dvec3 specular_reflected(const CubeLevel& source, const dvec3& n, const dvec3& v, double roughness, double f0,
                                uint32_t samples) {
  const double a2 = std::pow(roughness, 4.0), n_v = std::max(glm::dot(n, v), 1e-4);
  const dvec3 up = std::abs(n.y) < 0.999 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
  const dvec3 tangent = glm::normalize(glm::cross(up, n)), bitangent = glm::cross(n, tangent);
  dvec3 sum(0.0);
  for (uint32_t i = 0; i < samples; ++i) {
    const double xi = (i + 0.5) / samples, phi = 2.0 * std::numbers::pi * radical_inverse(i);
    const double cos_h = std::sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));
    const double sin_h = std::sqrt(std::max(1.0 - cos_h * cos_h, 0.0));
    const dvec3 h = tangent * (sin_h * std::cos(phi)) + bitangent * (sin_h * std::sin(phi)) + n * cos_h;
    const double v_h = glm::dot(v, h);
    const dvec3 l = 2.0 * v_h * h - v;
    const double n_l = glm::dot(n, l);
    if (n_l <= 0 || v_h <= 0) continue;
    const double visibility =
        0.5 / (n_l * std::sqrt(n_v * n_v * (1 - a2) + a2) + n_v * std::sqrt(n_l * n_l * (1 - a2) + a2));
    const double fresnel = f0 + (1 - f0) * std::pow(1 - v_h, 5.0);
    sum += sample(source, l) * (fresnel * visibility * 4.0 * v_h * n_l / cos_h);
  }
  return sum / double(samples);
}

// lighting.dfg's (scale, bias) at n·v and roughness from its side × side R16G16_SFLOAT table,
// bilinear between texel centres (which hold 0 and 1 at the ends) as the sampler reads it.
inline glm::dvec2 dfg_lookup(const std::vector<uint8_t>& table, uint32_t side, double n_v, double roughness) {
  const auto at = [&](int x, int y) {
    float t[4];
    decode_texel(*format_info(VK_FORMAT_R16G16_SFLOAT), 0, table,
                 uint64_t(std::clamp(y, 0, int(side) - 1)) * side + uint64_t(std::clamp(x, 0, int(side) - 1)), t);
    return glm::dvec2(t[0], t[1]);
  };
  const double fx = n_v * (side - 1), fy = roughness * (side - 1);
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const double tx = fx - x0, ty = fy - y0;
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), tx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), tx), ty);
}

// The radiance a white Lambertian surface of normal n reflects under the cube's light: the
// cosine-weighted sum over every texel, over π.
inline dvec3 diffuse_reflected(const CubeLevel& level, const dvec3& n) {
  dvec3 sum(0.0);
  for (uint32_t face = 0; face < 6; ++face)
    for (uint32_t y = 0; y < level.side; ++y)
      for (uint32_t x = 0; x < level.side; ++x) {
        const double cosine = glm::dot(n, texel_direction(face, x, y, level.side));
        if (cosine > 0) sum += level.at(face, x, y) * (cosine * texel_solid_angle(x, y, level.side));
      }
  return sum / std::numbers::pi;
}

// The real spherical harmonics of bands 0–2 (Ramamoorthi and Hanrahan 2001's normalisation).
inline std::array<double, 9> sh_basis(const dvec3& d) {
  return {0.5 * std::sqrt(1.0 / std::numbers::pi),
          std::sqrt(3.0 / (4.0 * std::numbers::pi)) * d.y,
          std::sqrt(3.0 / (4.0 * std::numbers::pi)) * d.z,
          std::sqrt(3.0 / (4.0 * std::numbers::pi)) * d.x,
          0.5 * std::sqrt(15.0 / std::numbers::pi) * d.x * d.y,
          0.5 * std::sqrt(15.0 / std::numbers::pi) * d.y * d.z,
          0.25 * std::sqrt(5.0 / std::numbers::pi) * (3.0 * d.z * d.z - 1.0),
          0.5 * std::sqrt(15.0 / std::numbers::pi) * d.x * d.z,
          0.25 * std::sqrt(15.0 / std::numbers::pi) * (d.x * d.x - d.y * d.y)};
}

// The cube's projection on sh_basis, convolved with the clamped cosine and over π (Â_l / π:
// 1, 2/3, 1/4), as sky.irradiance stores it.
inline std::array<dvec3, 9> sh_irradiance(const CubeLevel& level) {
  std::array<dvec3, 9> c{};
  for (uint32_t face = 0; face < 6; ++face)
    for (uint32_t y = 0; y < level.side; ++y)
      for (uint32_t x = 0; x < level.side; ++x) {
        const std::array<double, 9> basis = sh_basis(texel_direction(face, x, y, level.side));
        const dvec3 weighted = level.at(face, x, y) * texel_solid_angle(x, y, level.side);
        for (int i = 0; i < 9; ++i) c[i] += weighted * basis[i];
      }
  for (int i = 0; i < 9; ++i) c[i] *= i == 0 ? 1.0 : (i < 4 ? 2.0 / 3.0 : 0.25);
  return c;
}

inline dvec3 sh_evaluate(const std::array<dvec3, 9>& c, const dvec3& n) {
  const std::array<double, 9> basis = sh_basis(n);
  dvec3 sum(0.0);
  for (int i = 0; i < 9; ++i) sum += c[i] * basis[i];
  return sum;
}

}  // namespace nightcap::reference
