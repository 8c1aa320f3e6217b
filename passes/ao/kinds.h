// The resource kinds of the ambient-occlusion passes (passes/core/resource_kind.h).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {

// R8G8B8A8_UNORM: rgb 0.5·b + 0.5 of the bent normal b (world space, the zero vector where
// nothing was drawn), a the cosine-weighted visibility; the visibility cone around b has the
// half-angle asin(√a).
inline constexpr ResourceKind ao_bent{"ao_bent"};

}  // namespace nightcap::kinds
