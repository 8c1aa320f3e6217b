// What the sky's LUT passes share: how a LUT image is declared and how its compute pass is
// dispatched.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

// An RGBA16F lookup table sized by its pass's parameters `width` and `height`.
ImageDecl sky_lut_image();
// Fills the pass's `lut` output: a thread per texel, `samples` (and for sky.multiscattering
// `directions`) from the parameters; zeros, the LUT's clear value, when sky.atmosphere is
// empty (no directional light), so that the pass computes what skipping it leaves.
void dispatch_sky_lut(PassContext& ctx, const std::string& lut);

}  // namespace nightcap
