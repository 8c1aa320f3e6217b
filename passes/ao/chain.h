// What the ambient-occlusion chain's passes (ao.gtao → ao.filter → ao.temporal) share: one switch,
// and the images they pass along, each the bent normal and visibility of every half-resolution
// texel in one format, size and clear value.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

// A compute pass of the chain, named `name`: ao.enabled=0 skips it with the rest.
PassDecl ao_chain_pass(std::string name);
// ao.raw, ao.filtered and ao.bent: R8G8B8A8_UNORM at half the output's size (kinds::ao_bent),
// cleared to the zero vector and visibility 1, which occludes nothing.
ImageDecl ao_bent_image();
// ao.history: R16G16B16A16_SFLOAT at half size (kinds::ao_history), cleared to no frames.
ImageDecl ao_history_image();

}  // namespace nightcap
