// lighting.dfg (CPU): the split sum's DFG table (dfg.h), side × side R16G16_SFLOAT texels (scale,
// bias), n·v across and perceptual roughness down, computed by the project in double
// (tests/unit/dfg_test.cpp holds it to a quadrature of the BRDF). It depends on its parameters
// alone, so a process computes it once per pair and every frame copies it; the capture records
// it with the frame, so a replay of the composite needs nothing but its inputs. Never skipped:
// 2 KB and a copy.
#include "passes/lighting/dfg.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "passes/core/context.h"
#include "passes/core/format.h"
#include "passes/lighting/stage.h"

namespace nightcap {
namespace {

double radical_inverse(uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return double(i) * 0x1p-32;
}

// The table's halves, (scale, bias) per texel, row by row.
std::vector<uint16_t> dfg_halves(uint32_t side, uint32_t samples) {
  static std::mutex mutex;
  static std::map<std::pair<uint32_t, uint32_t>, std::vector<uint16_t>> tables;
  const std::lock_guard lock(mutex);
  std::vector<uint16_t>& table = tables[{side, samples}];
  if (table.empty()) {
    table.resize(size_t(side) * side * 2);
    for (uint32_t y = 0; y < side; ++y)
      for (uint32_t x = 0; x < side; ++x) {
        const DfgEntry e = dfg_entry(dfg_axis_value(x, side), dfg_axis_value(y, side), samples);
        table[(size_t(y) * side + x) * 2] = float_to_half(float(e.scale));
        table[(size_t(y) * side + x) * 2 + 1] = float_to_half(float(e.bias));
      }
  }
  return table;
}

}  // namespace

double dfg_axis_value(uint32_t index, uint32_t side) { return side > 1 ? double(index) / double(side - 1) : 0.0; }

DfgEntry dfg_entry(double n_v, double roughness, uint32_t samples) {
  n_v = std::max(n_v, 1e-4);
  const double alpha = roughness * roughness, a2 = alpha * alpha;
  const glm::dvec3 v(std::sqrt(std::max(1.0 - n_v * n_v, 0.0)), 0.0, n_v);
  DfgEntry sum;
  for (uint32_t i = 0; i < samples; ++i) {
    const double xi = (i + 0.5) / samples, phi = 2.0 * std::numbers::pi * radical_inverse(i);
    const double cos_h = std::sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));
    const double sin_h = std::sqrt(std::max(1.0 - cos_h * cos_h, 0.0));
    const glm::dvec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
    const double v_h = glm::dot(v, h);
    const glm::dvec3 l = 2.0 * v_h * h - v;
    const double n_l = l.z;
    if (n_l <= 0.0 || v_h <= 0.0) continue;
    // Height-correlated Smith: V = G / (4 n·l n·v), as brdf.glsl's v_smith_correlated.
    const double visibility =
        0.5 / (n_l * std::sqrt(n_v * n_v * (1.0 - a2) + a2) + n_v * std::sqrt(n_l * n_l * (1.0 - a2) + a2));
    // f · n·l over the pdf of l, D(h) n·h / (4 v·h): D cancels.
    const double weight = visibility * 4.0 * n_l * v_h / cos_h;
    const double fresnel = std::pow(1.0 - v_h, 5.0);
    sum.scale += (1.0 - fresnel) * weight;
    sum.bias += fresnel * weight;
  }
  return {sum.scale / samples, sum.bias / samples};
}

PassDecl lighting_dfg_pass() {
  ImageDecl table{VK_FORMAT_R16G16_SFLOAT, kinds::lookup_table};
  table.size.mode = SizeRule::Mode::square_param;
  table.size.param = "size";
  return PassDecl("lighting.dfg", PassType::cpu)
      .write("lighting.dfg", Use::host, table)
      .param_int("size", 32, 2, 256, "texels on a side: n·v across, roughness down")
      .param_int("samples", 1024, 1, 1 << 20, "GGX samples per texel")
      .run([](PassContext& ctx) {
        const std::vector<uint16_t> halves =
            dfg_halves(uint32_t(ctx.param_int("size")), uint32_t(ctx.param_int("samples")));
        std::vector<uint8_t>& out = ctx.output("lighting.dfg");
        out.resize(halves.size() * sizeof(uint16_t));
        std::memcpy(out.data(), halves.data(), out.size());
      });
}

}  // namespace nightcap
