// Storing to half-float targets. Vulkan leaves the rounding of a float→half store open and
// lavapipe truncates (up to a whole ULP low, 2⁻¹⁰ relative instead of 2⁻¹¹), and beyond 65504 a
// half is Inf, which every later pass would carry. A pass writing RGBA16F stores
// nearest_half(x): the half nearest to x (ties to even), at most 65504, which every device then
// stores exactly.
const float HALF_MAX = 65504.0;

vec3 nearest_half(vec3 x) {
  x = min(x, vec3(HALF_MAX));
  ivec3 e;
  frexp(x, e);
  // One half ULP at x; subnormal halves share 2⁻²⁴. frexp/ldexp keep the scaling exact.
  vec3 ulp = ldexp(vec3(1.0), max(e - 1, ivec3(-14)) - 10);
  return roundEven(x / ulp) * ulp;
}

// Signed targets (motion vectors, spherical-harmonic coefficients): the same rounding, limited to
// ±65504.
vec2 nearest_half(vec2 x) { return nearest_half(vec3(max(x, vec2(-HALF_MAX)), 0.0)).xy; }
vec4 nearest_half(vec4 x) {
  x = max(x, vec4(-HALF_MAX));
  return vec4(nearest_half(x.xyz), nearest_half(vec3(x.w, 0.0, 0.0)).x);
}

// B10G11R11_UFLOAT targets: the same rounding to their 6-bit (red, green) and 5-bit (blue)
// mantissas over half's exponent range, for non-negative x at most 65024, their largest value.
vec3 nearest_b10g11r11(vec3 x) {
  ivec3 e;
  frexp(x, e);
  vec3 ulp = ldexp(vec3(1.0), max(e - 1, ivec3(-14)) - ivec3(6, 6, 5));
  return roundEven(x / ulp) * ulp;
}
