// The GI volume as lighting.composite reads it: a point's irradiance about a normal, trilinear
// between the eight cells around it. Needs sh.glsl, volume_layout.glsl.h, `gi` (GpuGiVolume) and
// `gi_cells` (gi.volume, a sampler3D) declared.
#ifndef NIGHTCAP_GI_VOLUME_LOOKUP_GLSL
#define NIGHTCAP_GI_VOLUME_LOOKUP_GLSL

// The irradiance about n over π at the camera-relative `position` (irradiance_n) and how much of
// it to take: 1 within the outermost cells' centres, falling linearly to 0 over the half cell
// beyond them to the volume's faces, 0 outside. The coefficients are interpolated first (the
// irradiance is linear in them), with texel fetches and weights in float rather than a filtered
// read: a device's filter may quantise its weights (8 bits on many), and it cannot wrap the
// toroidal cells' seams per coefficient block. A cell that gathered nothing (band 0 zero: no
// probe's box holds it and the sky is not above it, as inside a building or under the ground) is
// left out and the others' weights renormalised, so that a wall's light is not darkened by the
// cells behind it; with all eight left out the volume has nothing there (0).
float gi_volume_irradiance(vec3 position, vec3 n, out vec3 irradiance_n) {
  irradiance_n = vec3(0.0);
  int cells = gi.origin_cell.w;
  vec3 f = (position - gi.origin.xyz) / gi.origin.w - 0.5;
  vec3 beyond = max(-f, f - float(cells - 1));
  float margin = max(max(beyond.x, beyond.y), beyond.z);
  if (!(margin < 0.5)) return 0.0;
  f = clamp(f, vec3(0.0), vec3(float(cells - 1)));
  ivec3 base = min(ivec3(floor(f)), ivec3(cells - 2));
  vec3 t = f - vec3(base);
  uint texels = gi.evaluation.y;
  vec4 sum[kGiVolumeTexels];
  for (int k = 0; k < int(kGiVolumeTexels); ++k) sum[k] = vec4(0.0);
  float total = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    vec3 axis_weight = mix(1.0 - t, t, vec3(offset));
    ivec3 texel = ((base + offset + gi.origin_cell.xyz) % cells + cells) % cells;
    vec4 first = texelFetch(gi_cells, texel, 0);
    float weight = first.r + first.g + first.b > 0.0 ? axis_weight.x * axis_weight.y * axis_weight.z : 0.0;
    total += weight;
    sum[0] += weight * first;
    for (uint k = 1u; k < texels; ++k)
      sum[k] += weight * texelFetch(gi_cells, ivec3(texel.xy, texel.z + int(k) * cells), 0);
  }
  if (!(total > 0.0)) return 0.0;
  float y[9];
  sh_basis(n, y);
  int coefficients = gi.evaluation.x == 1u ? 4 : 9;
  vec3 e = vec3(0.0);
  for (int i = 0; i < coefficients; ++i) {
    int j = 3 * i;
    e += vec3(sum[j / 4][j % 4], sum[(j + 1) / 4][(j + 1) % 4], sum[(j + 2) / 4][(j + 2) % 4]) * y[i];
  }
  irradiance_n = max(e / total, vec3(0.0));
  return clamp(1.0 - 2.0 * max(margin, 0.0), 0.0, 1.0);
}

#endif
