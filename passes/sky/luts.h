// What the sky's passes share: when they run, how a LUT image is declared and how a LUT pass is
// dispatched.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

// A pass of the sky, skipped with no directional light to light a sky and, the four together, by
// `--set sky.enabled=0` (the composite then draws its constant sky).
PassDecl sky_pass(std::string name, PassType type);
// An RGBA16F lookup table sized by its pass's parameters `width` and `height`.
ImageDecl sky_lut_image();
// Fills the pass's `lut` output: a thread per texel, `samples` (and for sky.multiscattering
// `directions`) from the parameters; zeros, the LUT's clear value, when sky.atmosphere is
// empty (no directional light), so that the pass computes what skipping it leaves.
void dispatch_sky_lut(PassContext& ctx, const std::string& lut);

}  // namespace nightcap
