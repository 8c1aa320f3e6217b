// The kinds of data the sky's passes write (registered in luts.cpp).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// An RGB table of the atmosphere (transmittance, multiple scattering, radiance) whose values span
// any range: drawn relative to its largest value.
inline constexpr ResourceKind sky_lut{"sky_lut"};
// The sky's radiance around the camera by direction from the light (sky.view): drawn as sky_lut
// is, and looked up by a world direction (`inspect direction`).
inline constexpr ResourceKind sky_view{"sky_view"};
// The sky's radiance as a cube map (sky.cubemap, sky.specular), drawn as sky_lut is.
inline constexpr ResourceKind sky_cube{"sky_cube"};
// The air along view rays (sky.aerial_perspective), per km of their length: rgb the radiance it
// scatters toward the camera, alpha the optical depth of its transmittance; drawn by the rgb, as
// sky_lut is.
inline constexpr ResourceKind aerial_perspective{"aerial_perspective"};
}  // namespace nightcap::kinds
