#version 460
layout(set = 0, binding = 0) uniform sampler2D lit_map;
layout(set = 0, binding = 1) uniform sampler2D exposure_value;  // 1×1; x: automatic exposure, 0: none
layout(set = 0, binding = 2) uniform sampler2D bloom_chain;
layout(push_constant) uniform Params {
  float exposure;
  float bloom;
};
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_ldr;

// Narkowicz's fit of the ACES filmic curve.
vec3 aces(vec3 x) { return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0); }

// The mean of the bloom levels at this pixel's centre, each interpolated bilinearly between its
// four nearest texels (clamped at the edges).
vec3 bloom_at(vec2 uv) {
  const int levels = textureQueryLevels(bloom_chain);
  vec3 sum = vec3(0.0);
  for (int level = 0; level < levels; ++level) {
    const ivec2 size = textureSize(bloom_chain, level);
    const vec2 t = uv * vec2(size) - 0.5;
    const vec2 f = t - floor(t);
    const ivec2 a = max(ivec2(floor(t)), ivec2(0)), b = min(ivec2(floor(t)) + 1, size - 1);
    sum +=
        mix(mix(texelFetch(bloom_chain, a, level).rgb, texelFetch(bloom_chain, ivec2(b.x, a.y), level).rgb, f.x),
            mix(texelFetch(bloom_chain, ivec2(a.x, b.y), level).rgb, texelFetch(bloom_chain, b, level).rgb, f.x), f.y);
  }
  return sum / float(levels);
}

void main() {
  const vec2 uv = gl_FragCoord.xy / vec2(textureSize(lit_map, 0));
  float automatic = texelFetch(exposure_value, ivec2(0), 0).x;
  vec3 hdr = (texelFetch(lit_map, ivec2(gl_FragCoord.xy), 0).rgb + bloom * bloom_at(uv)) *
             (exposure * (automatic > 0.0 ? automatic : 1.0));
  // A NaN (or 0 × Inf) must not reach the display. Test before any max() or clamp(): their
  // result for a NaN operand is undefined, and lavapipe's max() returns the other operand.
  if (any(isnan(hdr))) hdr = vec3(0.0);
  // The curve reaches 1 at x ≈ 7.24, so the upper clamp changes nothing but keeps +Inf out of
  // the Inf/Inf it would otherwise become.
  out_ldr = vec4(aces(clamp(hdr, 0.0, 16.0)), 1.0);  // the R8G8B8A8_SRGB target applies the sRGB encoding
}
