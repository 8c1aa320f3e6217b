// The kinds of data the sky's passes write (registered in luts.cpp).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// An RGB table of the atmosphere (transmittance, multiple scattering, radiance) whose values span
// any range: drawn relative to its largest value.
inline constexpr ResourceKind sky_lut{"sky_lut"};
// The sky's radiance as a cube map (sky.cubemap, sky.specular), drawn as sky_lut is.
inline constexpr ResourceKind sky_cube{"sky_cube"};
}  // namespace nightcap::kinds
