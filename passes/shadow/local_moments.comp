#version 460
// shadow.local_moments: a 16×16 tile of one map's moments, box-blurred (radius BLUR) through
// shared memory: linear depth and its square for the tile and its apron, then row sums, then
// column sums. The map's edge repeats its last texel.
layout(local_size_x = 16, local_size_y = 16) in;
layout(constant_id = 0) const int BLUR = 1;
// A layer without a map: its depth is 1 everywhere, so its moments are (1, 1). A constant, so
// that lavapipe does not run the blur's loads and barriers for the empty layers too.
layout(constant_id = 1) const bool EMPTY_LAYERS = false;

layout(std140, set = 0, binding = 0) uniform LocalBlock {
  vec4 clip_x[16], clip_y[16], clip_z[16], clip_w[16];  // rows of camera-relative world → clip
  vec4 depth_range[16];  // near, far, 1 / (far − near), light
  uvec4 counts;
};
layout(set = 0, binding = 1) uniform sampler2DArray depth_maps;
layout(set = 0, binding = 2, rg16) uniform writeonly image2DArray moments_out;

layout(push_constant) uniform Params { uint first_slice; };

const int kSide = 16 + 2 * BLUR;
shared vec2 texel_moments[kSide * kSide];
shared vec2 row_sums[16 * kSide];

void main() {
  int slice = int(first_slice + gl_WorkGroupID.z);
  int resolution = textureSize(depth_maps, 0).x;
  if (EMPTY_LAYERS) {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(pixel, ivec2(resolution)))) imageStore(moments_out, ivec3(pixel, slice), vec4(1.0, 1.0, 0.0, 0.0));
    return;
  }
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * 16 - BLUR;
  uint lane = gl_LocalInvocationIndex;
  vec4 range = depth_range[slice];
  for (uint i = lane; i < uint(kSide * kSide); i += 256u) {
    ivec2 texel = clamp(origin + ivec2(int(i) % kSide, int(i) / kSide), ivec2(0), ivec2(resolution - 1));
    float d = texelFetch(depth_maps, ivec3(texel, slice), 0).r;
    // Forward perspective depth back to the distance along the axis, then to [0, 1].
    float w = range.x * range.y / max(range.y - d * (range.y - range.x), 1e-30);
    float t = clamp((w - range.x) * range.z, 0.0, 1.0);
    texel_moments[i] = vec2(t, t * t);
  }
  barrier();
  for (uint i = lane; i < uint(16 * kSide); i += 256u) {
    int x = int(i) % 16, y = int(i) / 16;
    vec2 sum = vec2(0.0);
    for (int k = 0; k <= 2 * BLUR; ++k) sum += texel_moments[y * kSide + x + k];
    row_sums[i] = sum;
  }
  barrier();
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  vec2 sum = vec2(0.0);
  for (int k = 0; k <= 2 * BLUR; ++k) sum += row_sums[(local.y + k) * 16 + local.x];
  ivec2 pixel = origin + BLUR + local;
  if (all(lessThan(pixel, ivec2(resolution))))
    imageStore(moments_out, ivec3(pixel, slice), vec4(sum / float((2 * BLUR + 1) * (2 * BLUR + 1)), 0.0, 0.0));
}
