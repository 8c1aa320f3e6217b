// Specular occlusion from ao.bent's visibility cone (Jimenez et al. 2016): the share of the
// specular lobe, taken as a cone about its dominant direction, that lies inside the cone of
// unoccluded directions about the bent normal, whose half-angle is asin(√visibility). Both cones'
// solid angles and their overlap are exact (spherical caps); the lobe's cone is the one whose
// edge is where the GGX distribution falls to half its peak, doubled from half vectors to
// reflected directions: cos²θh = (1 − √2 α²) / (1 − α²), θ = min(2θh, π/2), a hemisphere from
// α² ≥ 1/√2 (roughness 0.92) on. Needs PI (../frame/types.glsl).

// The solid angle of the overlap of two spherical caps of half-angles a and b whose axes are d
// apart (Tovchigrechko and Vakser 2001).
float cap_overlap(float a, float b, float d) {
  if (d >= a + b) return 0.0;
  if (d <= abs(a - b)) return 2.0 * PI * (1.0 - cos(min(a, b)));
  float ca = cos(a), cb = cos(b), cd = cos(d), sa = sin(a), sb = sin(b), sd = sin(d);
  float between = acos(clamp((cd - ca * cb) / (sa * sb), -1.0, 1.0));
  float at_a = acos(clamp((cb - cd * ca) / (sd * sa), -1.0, 1.0));
  float at_b = acos(clamp((ca - cd * cb) / (sd * sb), -1.0, 1.0));
  return max(2.0 * (PI - between - at_a * ca - at_b * cb), 0.0);
}

// The half-angle of the specular lobe's cone at `roughness` (the material's, α = roughness²).
float specular_cone_angle(float roughness) {
  float alpha2 = roughness * roughness * roughness * roughness;
  float cos2 = (1.0 - sqrt(2.0) * alpha2) / max(1.0 - alpha2, 1e-6);
  return cos2 <= 0.0 ? 0.5 * PI : min(2.0 * acos(sqrt(min(cos2, 1.0))), 0.5 * PI);
}

// The share of the lobe about `r` (unit) inside the visibility cone about `bent` (any length; the
// zero vector: no cone, nothing occluded).
float cone_specular_occlusion(vec3 bent, float visibility, vec3 r, float roughness) {
  if (dot(bent, bent) < 1e-8) return 1.0;
  float visible = asin(sqrt(clamp(visibility, 0.0, 1.0)));
  float lobe = specular_cone_angle(roughness);
  float apart = acos(clamp(dot(normalize(bent), r), -1.0, 1.0));
  if (lobe < 1e-3) return apart <= visible ? 1.0 : 0.0;  // a mirror: its one direction
  return clamp(cap_overlap(visible, lobe, apart) / (2.0 * PI * (1.0 - cos(lobe))), 0.0, 1.0);
}
