// CPU references for the GI volume (passes/gi), shared by its unit tests and the benchmark: a
// cell as gi.volume stores it, decoded; the irradiance a point reads from the volume, by the
// trilinear formula and the bands' sum in double, written from volume_layout.glsl.h's
// definitions; and the error of spherical-harmonic irradiance against the exact.
#pragma once

#include <algorithm>
#include <array>
#include <cstring>
#include <glm/glm.hpp>
#include <numbers>
#include <vector>

#include "passes/core/format.h"
#include "passes/gi/volume_layout.h"
#include "passes/sky/ibl.glsl.h"
#include "tests/reference/ibl_reference.h"

namespace nightcap::reference {

// The texel of the world cell `cell` in a volume of `cells` per side.
inline glm::ivec3 gi_toroidal(const glm::ivec3& cell, int cells) { return ((cell % cells) + cells) % cells; }

// A cell's 27 numbers (and the unused 28th) at `texel` of gi.volume's bytes, decoded.
inline std::array<double, 28> gi_stored_cell(const std::vector<uint8_t>& volume, uint32_t cells,
                                             const glm::ivec3& texel) {
  std::array<double, 28> out{};
  for (uint32_t k = 0; k < kGiVolumeTexels; ++k) {
    const size_t index = ((size_t(texel.z) + size_t(k) * cells) * cells + size_t(texel.y)) * cells + size_t(texel.x);
    for (int m = 0; m < 4; ++m) {
      uint16_t h;
      std::memcpy(&h, volume.data() + index * 8 + size_t(m) * 2, 2);
      out[4 * k + m] = half_to_float(h);
    }
  }
  return out;
}

struct GiLookup {
  dvec3 irradiance_n{0.0};  // about the normal, over π
  double weight = 0.0;      // the volume's share against the sky's
  double band0 = 0.0;       // the mean over colours of the band-0 term c0 · Y0: the mean irradiance over π
};

// What a camera-relative point reads from the volume about n: the eight cells around it,
// trilinear, those that gathered nothing (band 0 zero) left out and the rest renormalised, then
// the first `bands` bands' sum; the weight 1 within the outermost cells' centres, falling to 0
// over the half cell beyond, 0 where all eight are left out.
inline GiLookup gi_lookup(const GpuGiVolume& volume, const std::vector<uint8_t>& bytes, const dvec3& position,
                          const dvec3& n, uint32_t bands) {
  const int cells = volume.origin_cell.w;
  dvec3 f = (position - dvec3(glm::vec3(volume.origin))) / double(volume.origin.w) - 0.5;
  const dvec3 beyond = glm::max(-f, f - double(cells - 1));
  const double margin = std::max({beyond.x, beyond.y, beyond.z});
  GiLookup out;
  if (margin >= 0.5) return out;
  f = glm::clamp(f, dvec3(0.0), dvec3(cells - 1));
  const glm::ivec3 base = glm::min(glm::ivec3(glm::floor(f)), glm::ivec3(cells - 2));
  const dvec3 t = f - dvec3(base);
  std::array<double, 28> sum{};
  double total = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::ivec3 offset(corner & 1, (corner >> 1) & 1, corner >> 2);
    const dvec3 w = glm::mix(1.0 - t, t, dvec3(offset));
    const std::array<double, 28> c =
        gi_stored_cell(bytes, uint32_t(cells), gi_toroidal(base + offset + glm::ivec3(volume.origin_cell), cells));
    if (!(c[0] + c[1] + c[2] > 0.0)) continue;
    total += w.x * w.y * w.z;
    for (int j = 0; j < 28; ++j) sum[j] += w.x * w.y * w.z * c[j];
  }
  if (!(total > 0.0)) return out;
  out.weight = std::clamp(1.0 - 2.0 * std::max(margin, 0.0), 0.0, 1.0);
  const std::array<double, 9> y = sh_basis(n);
  for (uint32_t k = 0; k < (bands == 1 ? 4u : 9u); ++k)
    out.irradiance_n += dvec3(sum[3 * k], sum[3 * k + 1], sum[3 * k + 2]) * y[k] / total;
  out.irradiance_n = glm::max(out.irradiance_n, dvec3(0.0));
  out.band0 = (sum[0] + sum[1] + sum[2]) / 3.0 * y[0] / total;
  return out;
}

// `count` unit normals spread evenly over the sphere (a Fibonacci lattice).
inline std::vector<dvec3> spread_normals(int count) {
  std::vector<dvec3> normals;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - y * y);
    normals.push_back(dvec3(r * std::cos(golden * i), y, r * std::sin(golden * i)));
  }
  return normals;
}

// The first `bands` bands (1: 0–1, 2: 0–2) of coefficients stored as sky.irradiance stores them.
inline std::array<dvec3, 9> sh_coefficients(const GpuSkyIrradiance& stored, uint32_t bands) {
  std::array<dvec3, 9> c{};
  for (uint32_t i = 0; i < (bands == 1 ? 4u : 9u); ++i) c[i] = dvec3(glm::vec3(stored.coefficients[i]));
  return c;
}

// How far irradiance from spherical harmonics is from the exact at each of `normals` (exact[i]
// at normals[i]), per colour: relative to the brightest normal's exact irradiance (Ramamoorthi
// and Hanrahan's measure: bands 0–2 of the clamped cosine are off by at most 9% of a point light's
// peak), the mean and the largest; and relative to each normal's own irradiance, the largest
// over the normals lit at least 10% of the brightest (below that a normal faces away from nearly
// all the light, and bands 0–2 cannot follow the terminator).
struct ShError {
  double mean = 0, largest = 0, largest_own = 0;
};
inline ShError sh_error(const std::array<dvec3, 9>& c, const std::vector<dvec3>& normals,
                        const std::vector<dvec3>& exact) {
  double brightest = 0;
  for (const dvec3& e : exact) brightest = std::max({brightest, e.x, e.y, e.z});
  ShError error;
  for (size_t i = 0; i < normals.size(); ++i) {
    const dvec3 banded = glm::max(sh_evaluate(c, normals[i]), dvec3(0.0));
    for (int k = 0; k < 3; ++k) {
      const double difference = std::abs(banded[k] - exact[i][k]);
      error.mean += difference / brightest;
      error.largest = std::max(error.largest, difference / brightest);
      if (exact[i][k] >= 0.1 * brightest) error.largest_own = std::max(error.largest_own, difference / exact[i][k]);
    }
  }
  error.mean /= double(3 * normals.size());
  return error;
}

}  // namespace nightcap::reference
