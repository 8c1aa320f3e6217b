// GGX prefiltering of an environment cube map for the split sum (Karis 2013), n = v = r, as
// sky.specular prefilters the sky and probes.convert a probe's capture: `samples` directions,
// GGX-distributed half vectors from a Hammersley set; each reads the source at the level whose
// texels subtend the sample's share of the lobe's solid angle (PDF-based mip selection, Colbert
// and Křivánek 2007, without their +1 bias, which doubled the error against the reference:
// tests/unit/sky_ibl_test.cpp), and counts by Smith's masking G1(l), which at n = v is the
// height-correlated G2 of the BRDF: the split sum is then exact at normal incidence, where
// Karis's n·l weight was 4% to 17% off the GGX integral on the sky of `--hour 17`.
// Needs brdf.glsl, and PREFILTER_SOURCE(direction, lod) defined as the source's radiance (rgb)
// along a world direction at a fractional level.
#ifndef NIGHTCAP_SKY_PREFILTER_GLSL
#define NIGHTCAP_SKY_PREFILTER_GLSL

vec2 hammersley(uint i, uint n) { return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10); }

// The radiance around n prefiltered at perceptual `roughness` (α its square), from a source cube
// of `source_size` texels a face at level 0 and `top_level` its last level.
vec3 ggx_prefiltered(vec3 n, float roughness, uint samples, float source_size, float top_level) {
  float alpha = roughness * roughness;
  vec3 up = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 tangent = normalize(cross(up, n)), bitangent = cross(n, tangent);
  float texel_solid_angle = 4.0 * PI / (6.0 * source_size * source_size);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (uint i = 0u; i < samples; ++i) {
    vec2 xi = hammersley(i, samples);
    float cos_h = sqrt((1.0 - xi.x) / (1.0 + (alpha * alpha - 1.0) * xi.x));
    float sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
    float phi = 2.0 * PI * xi.y;
    vec3 h = tangent * (sin_h * cos(phi)) + bitangent * (sin_h * sin(phi)) + n * cos_h;
    vec3 l = 2.0 * dot(n, h) * h - n;
    float n_l = dot(n, l);
    if (n_l <= 0.0) continue;
    // With n = v the pdf of l is D(h) / 4.
    float sample_solid_angle = 4.0 / (float(samples) * max(d_ggx(n, h, alpha), 1e-30));
    float lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle), 0.0, top_level);
    // G1(l) = 2 n·l / (n·l + sqrt(α² + (1 − α²) n·l²)).
    float masking = 2.0 * n_l / (n_l + sqrt(alpha * alpha + (1.0 - alpha * alpha) * n_l * n_l));
    sum += PREFILTER_SOURCE(l, lod) * masking;
    weight += masking;
  }
  return sum / max(weight, 1e-30);
}

#endif
