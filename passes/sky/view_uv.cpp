#include "passes/sky/view_uv.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nightcap {
namespace {

double texel_coordinate(double x, double n) { return 0.5 / n + x * (1.0 - 1.0 / n); }

}  // namespace

std::array<double, 2> sky_view_uv(const GpuAtmosphere& atmosphere, const std::array<double, 3>& direction,
                                  uint32_t width, uint32_t height) {
  const double ground = atmosphere.radii.x, top = atmosphere.radii.y;
  // camera_height.glsl: whole metres, kept a metre inside the atmosphere.
  const double h = std::clamp(double(atmosphere.light.w) * 1e-3, 1e-3, top - ground - 1e-3);
  const double below = std::acos(std::clamp(std::sqrt(h * (2.0 * ground + h)) / (ground + h), -1.0, 1.0));
  const double zenith_to_horizon = std::numbers::pi - below;
  const double length = std::hypot(direction[0], direction[1], direction[2]);
  const double zenith = std::acos(std::clamp(direction[1] / length, -1.0, 1.0));
  const double v =
      zenith <= zenith_to_horizon
          ? 0.5 * (1.0 - std::sqrt(std::max(1.0 - zenith / zenith_to_horizon, 0.0)))
          : 0.5 + 0.5 * std::sqrt(std::clamp((zenith - zenith_to_horizon) / std::max(below, 1e-6), 0.0, 1.0));
  // The azimuth from the light: the record's light.xyz is the way the light travels.
  const double view_x = direction[0], view_z = direction[2], light_x = -atmosphere.light.x,
               light_z = -atmosphere.light.z;
  const double view_flat = std::hypot(view_x, view_z), light_flat = std::hypot(light_x, light_z);
  const double cos_azimuth =
      view_flat > 1e-6 && light_flat > 1e-6 ? (view_x * light_x + view_z * light_z) / (view_flat * light_flat) : 1.0;
  const double u = std::sqrt(std::clamp(0.5 - 0.5 * cos_azimuth, 0.0, 1.0));
  return {texel_coordinate(u, width), texel_coordinate(v, height)};
}

}  // namespace nightcap
