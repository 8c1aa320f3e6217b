// The kinds of data the depth stage writes (registered beside their writers: depth.prepass,
// depth.convert, depth.pyramid).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// Device depth (reversed-Z, infinite far plane: d = znear / distance) and stencil tags.
inline constexpr ResourceKind depth_stencil{"depth_stencil"};
// Stencil tags (scene.h's classes and flags) outside a depth-stencil image.
inline constexpr ResourceKind stencil{"stencil"};
// Min and max linear depth in metres over each texel's footprint.
inline constexpr ResourceKind depth_minmax{"depth_minmax"};
}  // namespace nightcap::kinds
