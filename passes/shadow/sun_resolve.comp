#version 460
// shadow.sun_resolve: the sun's visibility at each pixel from shadow.cascades. The cascade is
// chosen by the pixel's view depth alone (interval-based selection [004 §2.2]); beyond the last
// split the pixel falls back to shadow.distant: the finest level whose map holds the filter's
// texels around it (none: unshadowed), with the same filter and biases. Visibility is the share
// of a (2·FILTER_RADIUS + 1)² block of texels around the pixel's light-space point whose stored
// depth is not nearer the sun than the receiver. The receiver's depth is carried to each texel's
// centre along its own plane (from gbuffer.normal): a receiver-plane bias, so a plane lit at a
// grazing angle does not shadow itself at the texels it slopes away from, and only depth_bias
// texels of constant bias are needed, which keeps the shadow's gap at a contact small. A texel
// at 1 holds no caster: lit, even for a receiver past the map's far depth. R: visibility; G: 1
// (free, frame.md).
#include "../frame/types.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int FILTER_RADIUS = 1;

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameConstants frame; };
layout(std140, set = 0, binding = 1) uniform CascadeBlock {
  mat4 light_from_world[4];
  vec4 splits;
  vec4 texel_metres;
  vec4 depth_metres;
  vec4 light_direction;
};
layout(set = 0, binding = 2) uniform sampler2D depth_map;
layout(set = 0, binding = 3) uniform sampler2D normal_map;
layout(set = 0, binding = 4) uniform sampler2DArray cascade_maps;
layout(std140, set = 0, binding = 5) uniform DistantBlock {
  mat4 distant_from_world[4];
  vec4 distant_texel_metres;
  vec4 distant_depth_metres;
  vec4 distant_light_direction;  // w: the levels' resolution
  ivec4 distant_refresh[4];
};
layout(set = 0, binding = 6) uniform sampler2DArray distant_maps;
layout(set = 0, binding = 7, rg8) uniform writeonly image2D sun_out;

layout(push_constant) uniform Params {
  float depth_bias;  // texels
  float max_slope;   // metres of light depth per metre across, at most (a receiver nearly edge-on)
};

// The filtered visibility from layer `layer` of `maps`, whose projection is m, texel and depth
// spans texel_m and depth_m, at resolution texels per side.
float map_visibility(sampler2DArray maps, int layer, mat4 m, float texel_m, float depth_m, float resolution,
                     vec3 position, vec3 n) {
  vec3 clip = (m * vec4(position, 1.0)).xyz;
  vec2 at = (clip.xy * 0.5 + 0.5) * resolution;  // in texels
  // The receiver's plane in light clip space: its depth change per texel along x and y.
  vec3 plane = transpose(inverse(mat3(m))) * n;
  float limit = max_slope * texel_m / depth_m;
  vec2 per_texel = abs(plane.z) > 1e-12 ? -plane.xy / plane.z * (2.0 / resolution) : vec2(0.0);
  per_texel = clamp(per_texel, vec2(-limit), vec2(limit));
  float bias = depth_bias * texel_m / depth_m;
  ivec2 base = ivec2(floor(at));
  int last = int(resolution) - 1;
  float lit = 0.0;
  for (int dy = -FILTER_RADIUS; dy <= FILTER_RADIUS; ++dy) {
    for (int dx = -FILTER_RADIUS; dx <= FILTER_RADIUS; ++dx) {
      ivec2 texel = base + ivec2(dx, dy);
      float expected = clip.z + dot(vec2(texel) + 0.5 - at, per_texel);
      bool inside = all(greaterThanEqual(texel, ivec2(0))) && all(lessThanEqual(texel, ivec2(last)));
      float stored = texelFetch(maps, ivec3(clamp(texel, ivec2(0), ivec2(last)), layer), 0).r;
      lit += (!inside || stored >= 1.0 || expected - bias <= stored) ? 1.0 : 0.0;
    }
  }
  float taps = float((2 * FILTER_RADIUS + 1) * (2 * FILTER_RADIUS + 1));
  return lit / taps;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewport.xy)))) return;
  float depth = texelFetch(depth_map, pixel, 0).r;
  float visibility = 1.0;
  if (depth > 0.0) {
    vec2 ndc = (vec2(pixel) + 0.5) * frame.viewport.zw * 2.0 - 1.0;
    vec4 p = frame.inverse_view_projection * vec4(ndc, depth, 1.0);
    vec3 position = p.xyz / p.w;  // camera-relative world, as lighting.tiled finds it
    float view_depth = frame.projection_params.x / depth;
    uint cascade = (view_depth > splits.x ? 1u : 0u) + (view_depth > splits.y ? 1u : 0u) +
                   (view_depth > splits.z ? 1u : 0u);
    vec3 n = texelFetch(normal_map, pixel, 0).xyz * 2.0 - 1.0;
    n = dot(n, n) > 1e-8 ? normalize(n) : vec3(0.0);
    if (view_depth <= splits.w) {
      visibility = map_visibility(cascade_maps, int(cascade), light_from_world[cascade], texel_metres[cascade],
                                  depth_metres[cascade], light_direction.w, position, n);
    } else {
      // The finest level that holds every texel the filter reads, with a texel to spare.
      float resolution = distant_light_direction.w;
      float reach = 2.0 * float(FILTER_RADIUS + 2) / max(resolution, 1.0);
      int level = 4;
      for (int k = 3; k >= 0; --k) {
        vec2 clip = (distant_from_world[k] * vec4(position, 1.0)).xy;
        if (all(lessThanEqual(abs(clip), vec2(1.0 - reach)))) level = k;
      }
      if (level < 4)
        visibility = map_visibility(distant_maps, level, distant_from_world[level], distant_texel_metres[level],
                                    distant_depth_metres[level], resolution, position, n);
    }
  }
  imageStore(sun_out, pixel, vec4(visibility, 1.0, 0.0, 0.0));
}
