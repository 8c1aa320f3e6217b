// The kind of data the sky's LUT passes write (registered beside them, in luts.cpp).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// An RGB table of the atmosphere (transmittance, multiple scattering, radiance) whose values span
// any range: drawn relative to its largest value.
inline constexpr ResourceKind sky_lut{"sky_lut"};
}  // namespace nightcap::kinds
