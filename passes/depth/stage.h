// The constructors of the depth stage's passes, which the frame's assembly (passes/assembly/registry.cpp)
// puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl depth_prepass_pass();
PassDecl depth_convert_pass();
PassDecl depth_pyramid_pass();

// depth.linear where nothing was drawn, by default (depth.convert's sky_depth): far beyond any
// surface of a 16 km map, and finite.
constexpr double kSkyDepth = 1e6;

}  // namespace nightcap
