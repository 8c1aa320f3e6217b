#version 460
// sky.specular, one level per dispatch: sky.cubemap prefiltered with GGX for the split sum (Karis
// 2013), n = v = r, at perceptual roughness level / (kSkySpecularMips − 1), α its square.
// `samples` directions per texel, GGX-distributed half vectors from a Hammersley set; each reads
// sky.cubemap at the level whose texels subtend the sample's share of the lobe's solid angle
// (PDF-based mip selection, Colbert and Křivánek 2007, without their +1 bias, which doubled the
// error against the reference: tests/unit/sky_ibl_test.cpp), and counts by Smith's masking G1(l),
// which at n = v is the height-correlated G2 of the BRDF: the split sum is then exact at normal
// incidence, where Karis's n·l weight was 4% to 17% off the GGX integral on the sky of
// `--hour 17` (tests/unit/sky_ibl_test.cpp). Level 0 (a
// mirror) is sky.cubemap read along each direction. Copied from the previous frame's when
// sky.atmosphere says the sky seen from the camera did not change.
#include "../frame/half.glsl"
#include "../frame/types.glsl"
#include "atmosphere.glsl.h"
#include "ibl.glsl.h"

layout(local_size_x = kSkyGroupSide, local_size_y = kSkyGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(sky_atmosphere)) uniform AtmosphereBlock { GpuAtmosphere atmosphere; };
layout(set = 0, binding = NC_BINDING(sky_cubemap)) uniform samplerCube sky_cube;
layout(set = 0, binding = NC_BINDING(sky_specular_previous)) uniform samplerCube previous_cube;
layout(set = 0, binding = NC_BINDING(sky_specular), rgba16f) uniform writeonly imageCube level_written;
layout(push_constant) uniform SkyCubeConstants { NC_BLOCK_MEMBERS(NC_SKY_CUBE_CONSTANTS_FIELDS) };

#include "../lighting/brdf.glsl"
#include "cube.glsl"

vec2 hammersley(uint i, uint n) { return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10); }

void main() {
  int size = imageSize(level_written).x;
  ivec3 texel = ivec3(gl_GlobalInvocationID);
  if (texel.x >= size || texel.y >= size) return;
  if (has_atmosphere == 0u) {
    imageStore(level_written, texel, vec4(0.0));
    return;
  }
  vec3 n = cube_texel_direction(uint(texel.z), texel.xy, size);
  if (atmosphere.changed.y == 0u) {
    // The texel's centre through a nearest sampler at this level: the previous frame's texel.
    imageStore(level_written, texel, textureLod(previous_cube, n, float(level)));
    return;
  }
  if (level == 0u) {
    imageStore(level_written, texel, vec4(nearest_half(textureLod(sky_cube, n, 0.0).rgb), 1.0));
    return;
  }
  float roughness = float(level) / float(kSkySpecularMips - 1u);
  float alpha = roughness * roughness;
  vec3 up = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 tangent = normalize(cross(up, n)), bitangent = cross(n, tangent);
  float source_size = float(textureSize(sky_cube, 0).x);
  float texel_solid_angle = 4.0 * PI / (6.0 * source_size * source_size);
  float top_level = float(textureQueryLevels(sky_cube) - 1);
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
    sum += textureLod(sky_cube, l, lod).rgb * masking;
    weight += masking;
  }
  imageStore(level_written, texel, vec4(nearest_half(sum / max(weight, 1e-30)), 1.0));
}
