#version 460
// sky.transmittance: at each texel's height and direction (transmittance_h_mu), the share of
// light that crosses the atmosphere from there to its top: exp(-optical depth), the optical
// depth a midpoint sum of the extinction over `samples` equal steps. Kept from the previous
// frame (a copy) when the atmosphere has not changed.
#include "../frame/half.glsl"
#include "atmosphere.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_transmittance_previous)) uniform sampler2D previous_lut;
layout(set = 0, binding = NC_BINDING(sky_transmittance), rgba16f) uniform writeonly image2D lut;
layout(push_constant) uniform SkyLutConstants { NC_BLOCK_MEMBERS(NC_SKY_LUT_CONSTANTS_FIELDS) };

#include "atmosphere.glsl"

void main() {
  ivec2 size = imageSize(lut);
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, size))) return;
  if (has_atmosphere == 0u) {
    imageStore(lut, texel, vec4(0.0));
    return;
  }
  if (atmosphere.changed.x == 0u) {
    imageStore(lut, texel, texelFetch(previous_lut, texel, 0));
    return;
  }
  float h, mu;
  transmittance_h_mu((vec2(texel) + 0.5) / vec2(size), vec2(size), h, mu);
  float step_km = distance_to_top(h, mu) / float(samples);
  vec3 depth = vec3(0.0);
  for (uint i = 0u; i < samples; ++i) depth += medium_at(height_along(h, mu, (float(i) + 0.5) * step_km)).extinction;
  imageStore(lut, texel, vec4(nearest_half(exp(-depth * step_km)), 1.0));
}
