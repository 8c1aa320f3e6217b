// The kinds taa writes (passes/taa/taa.cpp registers them): HDR colour whose alpha says, at a
// pixel, how the resolve treated the history.
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// taa.resolved: rgb the resolved colour, a the part of the history clipping removed.
inline constexpr ResourceKind taa_resolved{"taa_resolved"};
// taa.history: rgb the same colour, a the frames it averages.
inline constexpr ResourceKind taa_history{"taa_history"};
}  // namespace nightcap::kinds
