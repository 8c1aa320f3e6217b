// tonemap's colour pipeline, shared by tonemap.frag (per pixel) and tonemap.vert (once for the
// whole output when the graph knows the lit colour and bloom.chain to be uniform).
#include "tonemap.glsl.h"

layout(set = 0, binding = NC_BINDING(lit)) uniform sampler2D lit_map;
layout(set = 0, binding = NC_BINDING(exposure_value)) uniform sampler2D exposure_value;  // 1×1; x: automatic exposure, 0: none
layout(set = 0, binding = NC_BINDING(bloom_chain)) uniform sampler2D bloom_chain;
layout(push_constant) uniform TonemapConstants { NC_BLOCK_MEMBERS(NC_TONEMAP_CONSTANTS_FIELDS) };
// Every texel of the lit colour, and of each bloom level, is the same: the pipeline variant that
// evaluates the colour once, in the vertex shader.
layout(constant_id = 0) const bool uniform_inputs = false;

// Narkowicz's fit of the ACES filmic curve.
vec3 aces(vec3 x) { return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0); }

// a + (b − a)·t rather than mix(): equal neighbours give back exactly their value, so a uniform
// input gives the same result at every pixel, and tonemap.vert's one evaluation is every pixel's.
vec3 lerp_exact(vec3 a, vec3 b, float t) { return a + (b - a) * t; }

// The mean of the bloom levels at `uv`, each interpolated bilinearly between its four nearest
// texels (clamped at the edges).
vec3 bloom_at(vec2 uv) {
  const int levels = textureQueryLevels(bloom_chain);
  vec3 sum = vec3(0.0);
  for (int level = 0; level < levels; ++level) {
    const ivec2 size = textureSize(bloom_chain, level);
    const vec2 t = uv * vec2(size) - 0.5;
    const vec2 f = t - floor(t);
    const ivec2 a = max(ivec2(floor(t)), ivec2(0)), b = min(ivec2(floor(t)) + 1, size - 1);
    sum += lerp_exact(
        lerp_exact(texelFetch(bloom_chain, a, level).rgb, texelFetch(bloom_chain, ivec2(b.x, a.y), level).rgb, f.x),
        lerp_exact(texelFetch(bloom_chain, ivec2(a.x, b.y), level).rgb, texelFetch(bloom_chain, b, level).rgb, f.x),
        f.y);
  }
  return sum / float(levels);
}

// The display colour of `pixel`, whose centre is at `uv`.
vec4 display(ivec2 pixel, vec2 uv) {
  float automatic = texelFetch(exposure_value, ivec2(0), 0).x;
  vec3 hdr =
      (texelFetch(lit_map, pixel, 0).rgb + bloom * bloom_at(uv)) * (exposure * (automatic > 0.0 ? automatic : 1.0));
  // A NaN (or 0 × Inf) must not reach the display. Test before any max() or clamp(): their
  // result for a NaN operand is undefined, and lavapipe's max() returns the other operand.
  if (any(isnan(hdr))) hdr = vec3(0.0);
  // The curve reaches 1 at x ≈ 7.24, so the upper clamp changes nothing but keeps +Inf out of
  // the Inf/Inf it would otherwise become.
  return vec4(aces(clamp(hdr, 0.0, 16.0)), 1.0);  // the R8G8B8A8_SRGB target applies the sRGB encoding
}
