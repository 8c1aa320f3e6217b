// The resource kinds of the ambient-occlusion passes (passes/core/resource_kind.h); passes/ao/chain.cpp
// registers how inspect and the report read them.
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {

// R8G8B8A8_UNORM: rgb 0.5·b + 0.5 of the bent normal b (world space, the zero vector where
// nothing was drawn), a the cosine-weighted visibility; the visibility cone around b has the
// half-angle asin(√a). ao.raw, ao.filtered and ao.bent.
inline constexpr ResourceKind ao_bent{"ao_bent"};
// R16G16B16A16_SFLOAT, ao.history: rgb the bent normal scaled by the frames it averages (its
// length; 0: no history), a the visibility.
inline constexpr ResourceKind ao_history{"ao_history"};

}  // namespace nightcap::kinds
