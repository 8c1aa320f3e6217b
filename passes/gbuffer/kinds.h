// The kinds of data the G-buffer holds (registered beside gbuffer.opaque, their writer).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// 0.5n + 0.5 of a unit world normal; a 2-bit alpha marks hair.
inline constexpr ResourceKind normal{"normal"};
// Metalness, roughness, translucency, and emissive luminance L stored as log2(1 + L) / 16.
inline constexpr ResourceKind material{"material"};
// Screen-space motion, current − previous position, in UV units.
inline constexpr ResourceKind motion{"motion"};
// The material's ambient occlusion (glTF's occlusion texture): the share of indirect light that
// reaches the surface, 1 where nothing was drawn.
inline constexpr ResourceKind occlusion{"occlusion"};
}  // namespace nightcap::kinds
