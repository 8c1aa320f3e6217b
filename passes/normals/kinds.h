// The kind of data normals.pack writes (registered beside it).
#pragma once

#include "passes/core/resource_kind.h"

namespace nightcap::kinds {
// A best-fit normal as 8-bit codes (n = code · 2/255 − 1, unnormalised) and roughness in alpha.
inline constexpr ResourceKind packed_normal{"packed_normal"};
}  // namespace nightcap::kinds
