// The half-resolution rule every half output of the frame shares (depth.convert's depth.half and
// stencil.half, normals.half's normal and motion): half texel h covers the full texels
// 2h … 2h + 1, cut at the image's edge when a full size is odd, and takes all it stores from one
// of them, the nearest to the camera. The pair of outputs then describes one surface, and thin
// foreground survives the downsample instead of the sky behind it.

// The footprint of `half_texel`: its first and last full texels.
void half_footprint(ivec2 half_texel, ivec2 full_size, out ivec2 first, out ivec2 last) {
  first = 2 * half_texel;
  last = min(first + 1, full_size - 1);
}

// The footprint's nearest texel: the largest reversed-Z device depth; ties keep the first in row
// order, so the choice depends on the depths alone (the CPU references make the same one).
ivec2 half_source_texel(sampler2D device_depth, ivec2 half_texel) {
  ivec2 first, last;
  half_footprint(half_texel, textureSize(device_depth, 0), first, last);
  ivec2 nearest = first;
  float nearest_device = -1.0;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      float device = texelFetch(device_depth, ivec2(x, y), 0).r;
      if (device > nearest_device) {
        nearest = ivec2(x, y);
        nearest_device = device;
      }
    }
  return nearest;
}
