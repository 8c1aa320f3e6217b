// The atmosphere's record (atmosphere.glsl.h) on the C++ side: its size, its schema and the
// Earth it describes by default.
#pragma once

#include "passes/core/buffer_schema.h"
#include "passes/sky/atmosphere.glsl.h"

namespace nightcap {

static_assert(sizeof(GpuAtmosphere) == 8 * 16);

BufferSchema atmosphere_schema();

// Earth's clear-sky atmosphere as Hillaire (2020) gives it (after Bruneton 2017), per kilometre,
// with each constituent's density scaled by the factors (1: Earth's) and Mie's asymmetry g.
struct AtmosphereFactors {
  double rayleigh = 1.0, mie = 1.0, ozone = 1.0;
  double mie_g = 0.8, ground_albedo = 0.3;
};
GpuAtmosphere earth_atmosphere(const AtmosphereFactors& factors);

}  // namespace nightcap
