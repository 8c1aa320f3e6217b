// Where sky.view holds a world direction, on the host: the parameterisation of
// passes/sky/atmosphere.glsl (sky_view_uv) and view_lookup.glsl, for `inspect direction`.
#pragma once

#include <array>
#include <cstdint>

#include "passes/sky/atmosphere.glsl.h"

namespace nightcap {

// The uv in [0, 1]² of a width × height sky.view at which the composite reads the sky's radiance
// along unit `direction` (world: y up), for the light and camera height of `atmosphere`'s record.
std::array<double, 2> sky_view_uv(const GpuAtmosphere& atmosphere, const std::array<double, 3>& direction,
                                  uint32_t width, uint32_t height);

}  // namespace nightcap
