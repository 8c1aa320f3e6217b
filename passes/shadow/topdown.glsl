// Whether the sky is straight above a point, from shadow.topdown's map of the static scene's
// heights: lighting.composite and probes.light scale the sky's diffuse light by it. Needs
// topdown_layout.glsl.h, `topdown` (GpuTopdown) and `topdown_map` (shadow.topdown, a sampler2D)
// declared.
#ifndef NIGHTCAP_SHADOW_TOPDOWN_GLSL
#define NIGHTCAP_SHADOW_TOPDOWN_GLSL

// Height a surface may stand above the point and still count as the point's own (the D16 steps
// and a roof's top against the point on it).
const float kTopdownBiasMetres = 0.05;

// 1 where no static surface of the map lies above the camera-relative `position` pushed
// topdown.extent.w metres along its normal n (off its own wall or roof edge), 0 where one does;
// between, the four nearest texels' answers blended bilinearly, so the sky's edge under a roof
// is a texel wide rather than a step. 1 outside the map.
float topdown_sky_visibility(vec3 position, vec3 n) {
  vec3 clip = (topdown.map_from_world * vec4(position + n * topdown.extent.w, 1.0)).xyz;
  if (any(greaterThan(abs(clip.xy), vec2(1.0)))) return 1.0;
  int side = int(topdown.extent.z);
  vec2 at = (clip.xy * 0.5 + 0.5) * topdown.extent.z - 0.5;
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  // Stored depth grows downward: a surface above the point holds less than the point's depth.
  float lowest_above = clip.z - kTopdownBiasMetres / topdown.extent.y;
  float open[4];
  for (int k = 0; k < 4; ++k) {
    ivec2 texel = clamp(base + ivec2(k & 1, k >> 1), ivec2(0), ivec2(side - 1));
    open[k] = texelFetch(topdown_map, texel, 0).r >= lowest_above ? 1.0 : 0.0;
  }
  return mix(mix(open[0], open[1], f.x), mix(open[2], open[3], f.x), f.y);
}

#endif
