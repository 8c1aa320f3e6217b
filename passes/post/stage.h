// The constructors of the post stage's passes, which the frame's assembly
// (passes/assembly/registry.cpp) puts in the frame. Each reads the HDR colour by the name it is
// given (`lit`): the assembly says what comes before post.
#pragma once

#include <string>

#include "passes/core/pass.h"

namespace nightcap {

// bloom.chain's levels, one pass each (passes/post/bloom.cpp).
constexpr uint32_t kBloomLevels = 6;
PassDecl bloom_level_pass(uint32_t level, const std::string& lit);
PassDecl exposure_pass(const std::string& lit);
PassDecl tonemap_pass(const std::string& lit);

}  // namespace nightcap
