// GGX specular with height-correlated Smith visibility and Schlick Fresnel; Lambert diffuse.
// GGX's denominator (n·h)²(α²−1)+1 is sin²θh + α²cos²θh. Near the peak 1 − (n·h)² cancels in
// float (at α = 0.03² it lost 40% of D), so sin²θh comes from |n×h|², which keeps its precision.
float d_ggx(vec3 n, vec3 h, float alpha) {
  float a2 = alpha * alpha;
  vec3 nxh = cross(n, h);
  float n_h = dot(n, h);
  float d = dot(nxh, nxh) + n_h * n_h * a2;
  // With no roughness floor (α = 0) an exact mirror direction would give 0/0.
  return a2 / max(PI * d * d, 1e-30);
}

float v_smith_correlated(float n_v, float n_l, float alpha) {
  float a2 = alpha * alpha;
  float gv = n_l * sqrt(n_v * n_v * (1.0 - a2) + a2);
  float gl = n_v * sqrt(n_l * n_l * (1.0 - a2) + a2);
  return 0.5 / max(gv + gl, 1e-7);
}

vec3 f_schlick(vec3 f0, float v_h) {
  return f0 + (1.0 - f0) * pow(1.0 - v_h, 5.0);
}

// Radiance reflected toward v from irradiance `e` arriving along l (both parts already
// multiplied by n·l): Lambert for the diffuse part, GGX for the specular part.
vec3 diffuse_term(vec3 n, vec3 l, vec3 e, vec3 albedo, float metallic) {
  return albedo * (1.0 - metallic) * (1.0 / PI) * max(dot(n, l), 0.0) * e;
}

vec3 specular_term(vec3 n, vec3 v, vec3 l, vec3 e, vec3 albedo, float metallic, float alpha) {
  float n_l = dot(n, l);
  if (n_l <= 0.0) return vec3(0.0);
  float n_v = max(dot(n, v), 1e-4);
  vec3 h = normalize(l + v);
  vec3 f0 = mix(vec3(0.04), albedo, metallic);
  vec3 f = f_schlick(f0, clamp(dot(v, h), 0.0, 1.0));
  return f * (d_ggx(n, h, alpha) * v_smith_correlated(n_v, n_l, alpha)) * n_l * e;
}
