// What the sky's passes share: when they run, how a LUT or cube map image is declared and how
// a LUT or cube map pass is dispatched.
#pragma once

#include <functional>

#include "passes/core/pass.h"

namespace nightcap {

// A pass of the sky, skipped with no directional light to light a sky and, the four together, by
// `--set sky.enabled=0` (the composite then draws its constant sky).
PassDecl sky_pass(std::string name, PassType type);
// A pass of the sky whose shader marches view rays through the air (march.glsl): compute, reading
// frame.constants, sky.atmosphere and the transmittance and multiple-scattering LUTs (bilinear).
PassDecl sky_march_pass(std::string name);
// An RGBA16F lookup table of `kind` sized by its pass's parameters `width` and `height`.
ImageDecl sky_lut_image(ResourceKind kind);
// Fills the pass's `lut` output: a thread per texel, `samples` (and for sky.multiscattering
// `directions`) from the parameters; zeros, the LUT's clear value, when sky.atmosphere is
// empty (no directional light), so that the pass computes what skipping it leaves.
void dispatch_sky_lut(PassContext& ctx, const std::string& lut);

// 1 when sky.atmosphere holds a record this frame (a directional light lights a sky), else 0:
// the sky's shaders then write their outputs' clear value, zeros.
uint32_t has_atmosphere(const PassContext& ctx);
// A cube map of `format` whose faces are the writing pass's parameter `size` texels wide, with
// `mips` mips (0: the whole chain).
ImageDecl sky_cube_image(VkFormat format, uint32_t mips);
// Fills cube map `cube` a mip level per dispatch, a thread per texel of its six faces, each level
// bound as PassDecl::level_mips declares it, the push constants SkyCubeConstants with
// `samples(level)`; with `in_order`, each level waits for the one before (it reads it).
void dispatch_sky_cube_levels(PassContext& ctx, const std::string& cube,
                              const std::function<uint32_t(uint32_t level)>& samples, bool in_order);

}  // namespace nightcap
