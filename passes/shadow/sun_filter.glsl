// The sun's shadow filter on one map (a cascade or a distant level), as shadow.sun_resolve
// filters the frame's pixels and the reflection probes' captures filter their faces: the
// receiver's depth carried to each texel along its own plane, then a depth test per texel
// (sun_resolve.comp says why). Needs shadow_layout.glsl.h.

// Where a pixel reads its shadow: a layer of the cascades or of the distant levels, its
// projection, a texel's side and the light depth [0, 1] spans in metres, texels per side.
struct ShadowMap {
  int layer;
  mat4 m;
  float texel_m, depth_m, resolution;
};

// The receiver's depth, its plane's slope per texel and the bias, carried to the texels the filter reads.
struct Receiver {
  vec2 at;  // in texels
  float depth, bias;
  vec2 per_texel;
};

// `slope_limit`: the largest receiver slope carried to the filter's texels; `bias_texels`: texels
// of light depth the receiver may lie behind the map and stay lit.
Receiver receiver_in(ShadowMap map, vec3 position, vec3 n, float slope_limit, float bias_texels) {
  Receiver r;
  vec3 clip = (map.m * vec4(position, 1.0)).xyz;
  r.at = (clip.xy * 0.5 + 0.5) * map.resolution;
  r.depth = clip.z;
  // The receiver's plane in light clip space: its depth change per texel along x and y.
  vec3 plane = transpose(inverse(mat3(map.m))) * n;
  float limit = slope_limit * map.texel_m / map.depth_m;
  vec2 per_texel = abs(plane.z) > 1e-12 ? -plane.xy / plane.z * (2.0 / map.resolution) : vec2(0.0);
  r.per_texel = clamp(per_texel, vec2(-limit), vec2(limit));
  r.bias = bias_texels * map.texel_m / map.depth_m;
  return r;
}

// Whether the filter's tap at `texel` is lit: outside the map, no caster (1) or the receiver not
// behind the stored depth.
bool tap_lit(Receiver r, ivec2 texel, float stored, int last) {
  float expected = r.depth + dot(vec2(texel) + 0.5 - r.at, r.per_texel);
  bool inside = all(greaterThanEqual(texel, ivec2(0))) && all(lessThanEqual(texel, ivec2(last)));
  return !inside || stored >= 1.0 || expected - r.bias <= stored;
}

// How many of the filter's `taps` around the receiver are lit, on layer `layer` of `maps`: taps
// is (2·radius + 1)², or 0 where the point reads another map (a loop of 0 iterations, whose body
// lavapipe skips for a row of pixels that none enters; an if would run it whole).
float lit_taps(sampler2DArray maps, int layer, Receiver r, int radius, int last, int taps) {
  ivec2 base = ivec2(floor(r.at));
  int side = 2 * radius + 1;
  float lit = 0.0;
  for (int i = 0; i < taps; ++i) {
    ivec2 texel = base + ivec2(i % side, i / side) - radius;
    float stored = texelFetch(maps, ivec3(clamp(texel, ivec2(0), ivec2(last)), layer), 0).r;
    lit += tap_lit(r, texel, stored, last) ? 1.0 : 0.0;
  }
  return lit;
}

// The finest of shadow.distant's levels whose map holds every texel a filter of `radius` reads
// around the point, with a texel to spare; kDistantLevels when none does (unshadowed).
int distant_level(GpuDistantLevels levels, vec3 position, int radius) {
  float reach = 2.0 * float(radius + 2) / max(levels.light_direction.w, 1.0);
  int level = int(kDistantLevels);
  for (int k = int(kDistantLevels) - 1; k >= 0; --k) {
    vec2 clip = (levels.light_from_world[k] * vec4(position, 1.0)).xy;
    if (all(lessThanEqual(abs(clip), vec2(1.0 - reach)))) level = k;
  }
  return level;
}
