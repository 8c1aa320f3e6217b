#version 460
// motion.stencil: 1 where a texel within `radius` (a square window, Chebyshev distance) is tagged
// moving, hair or foliage; 0 elsewhere.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform usampler2D stencil_map;
layout(set = 0, binding = 1, r8ui) uniform writeonly uimage2D motion_mask;
layout(push_constant) uniform Params { int radius; };

// passes/scene/scene.h: the classes use bits 0xB5, so road (0x08) and vehicle (0x40) marks OR-ed
// onto a class leave it recognisable.
const uint MOVING = 0x02u, CLASS_BITS = 0xB5u, HAIR = 0x95u, FOLIAGE = 0xA0u;

bool tagged(uint stencil) {
  uint tag_class = stencil & CLASS_BITS;
  return (stencil & MOVING) != 0u || tag_class == HAIR || tag_class == FOLIAGE;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = textureSize(stencil_map, 0);
  if (any(greaterThanEqual(p, size))) return;
  ivec2 first = max(p - radius, ivec2(0)), last = min(p + radius, size - 1);
  uint masked = 0u;
  for (int y = first.y; y <= last.y && masked == 0u; ++y)
    for (int x = first.x; x <= last.x; ++x)
      if (tagged(texelFetch(stencil_map, ivec2(x, y), 0).r)) {
        masked = 1u;
        break;
      }
  imageStore(motion_mask, p, uvec4(masked));
}
