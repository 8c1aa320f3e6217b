#version 460
// shadow.distant: what a level keeps from the previous frame, drawn over the whole layer before
// the casters. A texel of a tile redrawn this frame, or one the previous frame's level did not
// cover (the level moved), starts at 1 (no occluder); any other reads the previous frame's texel
// that covers the same place (refresh.xy: the level's move in whole texels).
layout(std140, set = 0, binding = 0) uniform DistantBlock {
  mat4 light_from_world[4];
  vec4 texel_metres;
  vec4 depth_metres;
  vec4 light_direction;
  ivec4 refresh[4];
};
layout(set = 0, binding = 1) uniform sampler2DArray previous_levels;

layout(push_constant) uniform Params { uint level; };

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  int resolution = int(light_direction.w);
  ivec4 r = refresh[level];
  ivec2 tile = texel / (resolution / r.w);
  bool redrawn = ((r.z >> (tile.y * r.w + tile.x)) & 1) != 0;
  ivec2 before = texel + r.xy;
  bool covered = all(greaterThanEqual(before, ivec2(0))) && all(lessThan(before, ivec2(resolution)));
  float kept = texelFetch(previous_levels, ivec3(clamp(before, ivec2(0), ivec2(resolution - 1)), int(level)), 0).r;
  gl_FragDepth = (!redrawn && covered) ? kept : 1.0;
}
