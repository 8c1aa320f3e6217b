// The second factor of the split sum (Karis 2013, "Real Shading in Unreal Engine 4"): GGX's
// directional albedo with height-correlated Smith visibility (passes/lighting/brdf.glsl) and
// Schlick's Fresnel, which is linear in F0: albedo(F0) = F0 · scale + bias. lighting.dfg tabulates
// it; the composite reads it for image-based specular light and for the multiple-scattering
// compensation (Fdez-Agüera 2019), whose single-scattering albedo at F0 = 1 is scale + bias.
#pragma once

#include <cstdint>

namespace nightcap {

struct DfgEntry {
  double scale = 0, bias = 0;
};

// Estimated in double from `samples` GGX-distributed half vectors of a Hammersley set, at
// α = roughness²; n·v below 10⁻⁴ counts as 10⁻⁴, as the shaders clamp it.
DfgEntry dfg_entry(double n_v, double roughness, uint32_t samples);

// Texel (x, y) of a side × side table holds n·v = x / (side − 1) and roughness y / (side − 1),
// so that a bilinear lookup at texel centres (x + 0.5) / side spans [0, 1] on both axes.
double dfg_axis_value(uint32_t index, uint32_t side);

}  // namespace nightcap
