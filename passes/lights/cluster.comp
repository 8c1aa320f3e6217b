#version 460
// lights.cluster, in four phases of one pass (each a dispatch and its own pipeline, ordered by
// the pass's storage barriers); passes/lights/cluster_layout.h says how froxels divide the view.
//   0: a workgroup per block of kClusterBlock² tiles lists, in ascending order, the local lights
//      whose bound reaches the block's view-space box (the box of its tiles' depth range) in
//      lights.cluster_blocks, so that a tile tests those rather than every light of the frame:
//      on the 16 km map thousands of lights survive the frame's culling and most tiles see a
//      few. A block whose list outgrows its slot of the buffer (or max_block_lights) is marked,
//      and its tiles test every light;
//   1: a workgroup per tile, an invocation per depth slice: count the lights of the tile's
//      block list whose bound reaches each froxel (stored in lights.clusters' second channel for
//      phase 2);
//   2: one workgroup turns the counts into offsets in froxel order (x, then y, then slice), each
//      count capped at max_lights_per_froxel and the running total at max_indices, and writes
//      lights.cluster_stats;
//   3: per tile again, the same tests write each froxel's list (ascending light indices) at its
//      offset, and the workgroups together zero the index buffer past the last entry.
// Nothing depends on execution order (integer sums, no atomics on the lists): every run writes
// the same bytes.
//
// The test (conservative; tests/reference/cluster_reference.h repeats it in double precision):
// a light with a range reaches a froxel when its core — the point of a point or spot light (a
// spot is bounded by its sphere, not its cone), the segment of a tube — lies within r' of the
// froxel's view-space bounding box, and outside none of the tile's four side planes by more than
// r', where r' = range + 2^-12 · (range + the farthest end's distance from the camera) pads the
// float arithmetic. The froxel's depth range is its slice's clipped to the tile's [min, max]
// linear depth from depth.pyramid (the level whose texel covers the tile), so a froxel between
// or beyond the tile's surfaces is empty. A light of range 0 reaches every non-empty froxel;
// directional lights are not clustered.
//
// The block's test keeps every light that any of its froxels keeps: a froxel's box lies in its
// tile's box, which lies in the block's (the same products of larger extents and a wider depth
// range), and the distance to a box is never more than to a box inside it; r' is padded by 2^-10
// more there against the rounding of the two distances. The block has no side-plane test: a side
// plane of a block is not a side plane of its tiles, and behind the camera a light can lie
// outside the block's plane and inside the tile's.
#include "../frame/types.glsl"
#include "cluster_layout.glsl.h"

// The froxels' shape, lights.cluster's parameters: the workgroup is one invocation per slice.
layout(local_size_x_id = 0) in;
const uint kSlices = gl_WorkGroupSize.x;
layout(constant_id = 1) const uint kTile = 32u;  // pixels on a side of a tile
layout(constant_id = 2) const uint phase = 0u;   // one pipeline per phase (cluster.cpp says why)

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
#include "../frame/camera.glsl"
layout(std430, set = 0, binding = NC_BINDING(frame_lights)) readonly buffer LightBlock { GpuLight lights[]; };
layout(set = 0, binding = NC_BINDING(depth_pyramid)) uniform sampler2D pyramid;
layout(set = 0, binding = NC_BINDING(lights_clusters), rg32ui) uniform uimage3D clusters;
layout(std430, set = 0, binding = NC_BINDING(lights_cluster_indices)) buffer IndexBlock { uint indices[]; };
layout(std430, set = 0, binding = NC_BINDING(lights_cluster_stats)) buffer StatsBlock { GpuClusterStats stats; };

// Per block, a slot of block_slot() words: the count (kOverflow when the list did not fit), then
// the list.
layout(std430, set = 0, binding = NC_BINDING(lights_cluster_blocks)) buffer BlockListBlock { uint block_lists[]; };
layout(push_constant) uniform ClusterConstants { NC_BLOCK_MEMBERS(NC_CLUSTER_CONSTANTS_FIELDS) };

const uint kNone = 0u, kBounded = 1u, kEverywhere = 2u;
const uint kOverflow = 0xffffffffu;

uvec2 block_count() { return (uvec2(tiles_x, tiles_y) + kClusterBlock - 1u) / kClusterBlock; }
uint block_slot() { return uint(block_lists.length()) / (block_count().x * block_count().y); }

// The chunk of lights (one per invocation) the workgroup tests together: view-space ends, padded
// range, reach; and those that reach the tile at all, in ascending order.
shared vec4 chunk_a[kSlices];  // xyz: first end, w: r'
shared vec3 chunk_b[kSlices];  // second end (= first for point and spot lights)
shared uint chunk_reach[kSlices];
shared uint chunk_tile[kSlices];
shared uint chunk_tile_count;
shared uint chunk_light[kSlices];  // the light each invocation classified

uint add_saturated(uint a, uint b) { return a > 0xffffffffu - b ? 0xffffffffu : a + b; }

// Per-axis offset of p from the box [lo, hi] (0 inside its slab).
vec3 outside(vec3 p, vec3 lo, vec3 hi) { return p - clamp(p, lo, hi); }

// Squared distance from the segment a + t·d, t in [0, 1], to the box [lo, hi]. The squared
// offset is convex and piecewise quadratic in t; its derivative (up to 2) dot(outside, d) is
// piecewise linear and non-decreasing, with kinks where the segment crosses a face plane. The
// minimum lies where the derivative changes sign: between the last kink (or 0) where it is
// ≤ 0 and the first (or 1) where it is ≥ 0 it is linear, so the root is interpolated there.
float segment_box_distance2(vec3 a, vec3 d, vec3 lo, vec3 hi) {
  float t_low = 0.0, t_high = 1.0;
  float s_low = dot(outside(a, lo, hi), d), s_high = dot(outside(a + d, lo, hi), d);
  float t = 0.0;
  if (s_low >= 0.0) {
    t = 0.0;
  } else if (s_high <= 0.0) {
    t = 1.0;
  } else {
    for (int axis = 0; axis < 3; ++axis) {
      if (d[axis] == 0.0) continue;
      for (int side = 0; side < 2; ++side) {
        float c = ((side == 0 ? lo[axis] : hi[axis]) - a[axis]) / d[axis];
        if (!(c > 0.0 && c < 1.0)) continue;
        float s = dot(outside(a + c * d, lo, hi), d);
        if (s <= 0.0 && c > t_low) {
          t_low = c;
          s_low = s;
        }
        if (s >= 0.0 && c < t_high) {
          t_high = c;
          s_high = s;
        }
      }
    }
    t = s_high > s_low ? t_low + (t_high - t_low) * (-s_low / (s_high - s_low)) : t_low;
  }
  vec3 e = outside(a + t * d, lo, hi);
  return dot(e, e);
}

// The view-space box of the tile's cell between linear depths near and far (view looks down −z).
void cell_box(vec4 extent, float near, float far, out vec3 lo, out vec3 hi) {
  vec4 at_near = extent * near, at_far = extent * far;
  lo = vec3(min(at_near.x, at_far.x), min(at_near.y, at_far.y), -far);
  hi = vec3(max(at_near.z, at_far.z), max(at_near.w, at_far.w), -near);
}

bool reaches(uint j, vec3 lo, vec3 hi) {
  if (chunk_reach[j] == kEverywhere) return true;
  vec4 a = chunk_a[j];
  return segment_box_distance2(a.xyz, chunk_b[j] - a.xyz, lo, hi) <= a.w * a.w;
}

// The lateral extent per metre of depth of the pixels [first, last): x in [extent.x, extent.z]·d,
// y in [extent.y, extent.w]·d.
vec4 screen_extent(vec2 first, vec2 last) {
  vec2 ndc0 = first / camera.viewport.xy * 2.0 - 1.0, ndc1 = last / camera.viewport.xy * 2.0 - 1.0;
  float sx = 1.0 / camera.projection[0][0], sy = -1.0 / camera.projection[1][1];
  return vec4(ndc0.x * sx, -ndc1.y * sy, ndc1.x * sx, -ndc0.y * sy);
}

// A light's view-space ends (b = a for point and spot lights) and padded range r'; kNone for
// directional lights.
uint light_core(uint i, out vec3 a, out vec3 b, out float r) {
  a = vec3(0.0);
  b = vec3(0.0);
  r = 0.0;
  GpuLight light = lights[i];
  if (uint(light.position_type.w) == kLightDirectional) return kNone;
  float range = light.color_range.w;
  if (range <= 0.0) return kEverywhere;
  mat3 view = mat3(camera.view);
  a = view * light.position_type.xyz;
  b = uint(light.position_type.w) == kLightTube ? view * light.end_radius.xyz : a;
  r = range + exp2(-12.0) * (range + max(length(a), length(b)));
  return kBounded;
}

// Phase 0: the block's list. Its depth range is the union of its tiles' (depth.pyramid's texels
// at the tiles' level), so its box holds each of their boxes.
void build_block_list() {
  uvec2 block = gl_WorkGroupID.xy;
  uint lane = gl_LocalInvocationID.x;
  uvec2 first_tile = block * kClusterBlock, end_tile = min(first_tile + kClusterBlock, uvec2(tiles_x, tiles_y));
  ivec2 level_size = textureSize(pyramid, pyramid_level);
  vec2 depth_range = vec2(3.0e38, -3.0e38);
  for (uint y = first_tile.y; y < end_tile.y; ++y)
    for (uint x = first_tile.x; x < end_tile.x; ++x) {
      vec2 d = texelFetch(pyramid, min(ivec2(x, y), level_size - 1), pyramid_level).rg;
      depth_range = vec2(min(depth_range.x, d.x), max(depth_range.y, d.y));
    }
  vec2 first = vec2(first_tile * kTile), last = min(vec2(end_tile * kTile), camera.viewport.xy);
  vec3 lo, hi;
  cell_box(screen_extent(first, last), depth_range.x, depth_range.y, lo, hi);

  uint slot = (block.y * block_count().x + block.x) * block_slot();
  uint capacity = min(max_block_lights, max(block_slot(), 1u) - 1u);
  uint count = 0u;
  uint light_count = frame.counts.x;
  for (uint base = 0u; base < light_count; base += kSlices) {
    uint i = base + lane;
    uint reach = kNone;
    if (i < light_count) {
      vec3 a, b;
      float r;
      reach = light_core(i, a, b, r);
      r *= 1.0 + exp2(-10.0);
      if (reach == kBounded && segment_box_distance2(a, b - a, lo, hi) > r * r) reach = kNone;
    }
    chunk_reach[lane] = reach;
    barrier();
    if (lane == 0u) {
      for (uint j = 0u; j < kSlices; ++j) {
        if (chunk_reach[j] == kNone) continue;
        if (count < capacity) block_lists[slot + 1u + count] = base + j;
        ++count;
      }
    }
    barrier();
  }
  // The count is lane 0's; the slot's unused words are zero, so the buffer is defined.
  if (lane == 0u) chunk_tile_count = count;
  barrier();
  count = chunk_tile_count;
  if (lane == 0u) block_lists[slot] = count > capacity ? kOverflow : count;
  for (uint k = min(count, capacity) + lane; k < capacity; k += kSlices) block_lists[slot + 1u + k] = 0u;
  // The words past the last slot (the buffer's length is rarely a multiple of the blocks).
  uint blocks = block_count().x * block_count().y;
  if (block.x == 0u && block.y == 0u)
    for (uint k = blocks * block_slot() + lane; k < uint(block_lists.length()); k += kSlices) block_lists[k] = 0u;
}

// Phases 1 and 3: the lights reaching each froxel of this invocation's tile and slice, counted
// (phase 1) or written (phase 3) in ascending order.
void build_lists() {
  uvec2 tile = gl_WorkGroupID.xy;
  uint slice = gl_LocalInvocationID.x;
  ivec2 level_size = textureSize(pyramid, pyramid_level);
  vec2 depth_range = texelFetch(pyramid, min(ivec2(tile), level_size - 1), pyramid_level).rg;

  float znear = camera.projection_params.x;
  float far = max(max_distance, 2.0 * znear);
  float step = log2(far / znear) / float(kSlices);
  float near = slice == 0u ? 0.0 : znear * exp2(float(slice) * step);
  float deep = slice == kSlices - 1u ? 3.0e38 : znear * exp2(float(slice + 1u) * step);
  near = max(near, depth_range.x);
  deep = min(deep, depth_range.y);
  bool occupied = near <= deep;

  vec2 first = vec2(tile * kTile), last = min(vec2((tile + 1u) * kTile), camera.viewport.xy);
  vec4 extent = screen_extent(first, last);
  // The tile's side planes through the camera, normals inward.
  vec3 planes[4] = vec3[4](normalize(vec3(1.0, 0.0, extent.x)), normalize(vec3(0.0, 1.0, extent.y)),
                           normalize(vec3(-1.0, 0.0, -extent.z)), normalize(vec3(0.0, -1.0, -extent.w)));
  vec3 tile_lo, tile_hi, lo, hi;
  cell_box(extent, depth_range.x, depth_range.y, tile_lo, tile_hi);
  cell_box(extent, near, deep, lo, hi);

  uint offset = 0u, stored = 0u;
  if (phase == 3u) {
    uvec2 list = imageLoad(clusters, ivec3(tile, slice)).xy;
    offset = list.x;
    stored = list.y;
  }
  // The lights to test: the block's list, or every light when it did not fit.
  uvec2 block = tile / kClusterBlock;
  uint slot = (block.y * block_count().x + block.x) * block_slot();
  uint block_lights = block_lists[slot];
  bool every_light = block_lights == kOverflow;
  uint light_count = every_light ? frame.counts.x : block_lights;
  uint count = 0u;
  for (uint base = 0u; base < light_count; base += kSlices) {
    // Each invocation classifies one light of the chunk against the whole tile.
    uint k = base + gl_LocalInvocationID.x;
    uint i = every_light ? k : block_lists[slot + 1u + min(k, max(block_slot(), 2u) - 2u)];
    uint reach = kNone;
    vec3 a = vec3(0.0), b = vec3(0.0);
    float r = 0.0;
    if (k < light_count) {
      reach = light_core(i, a, b, r);
      if (reach == kBounded) {
        for (int p = 0; p < 4; ++p)
          if (max(dot(planes[p], a), dot(planes[p], b)) < -r) reach = kNone;
        if (reach == kBounded && segment_box_distance2(a, b - a, tile_lo, tile_hi) > r * r) reach = kNone;
      }
    }
    chunk_a[gl_LocalInvocationID.x] = vec4(a, r);
    chunk_b[gl_LocalInvocationID.x] = b;
    chunk_reach[gl_LocalInvocationID.x] = reach;
    chunk_light[gl_LocalInvocationID.x] = i;
    barrier();
    // Most lights miss most tiles: each slice then tests only those that reach the tile.
    if (gl_LocalInvocationID.x == 0u) {
      uint n = 0u;
      for (uint j = 0u; j < kSlices; ++j)
        if (chunk_reach[j] != kNone) chunk_tile[n++] = j;
      chunk_tile_count = n;
    }
    barrier();
    if (occupied) {
      for (uint c = 0u; c < chunk_tile_count; ++c) {
        uint j = chunk_tile[c];
        if (!reaches(j, lo, hi)) continue;
        if (phase == 3u && count < stored) indices[offset + count] = chunk_light[j];
        ++count;
      }
    }
    barrier();
  }
  if (phase == 1u) imageStore(clusters, ivec3(tile, slice), uvec4(0u, count, 0u, 0u));
}

// Phase 2: offsets from the counts, in one workgroup (each invocation a run of froxels), and the
// statistics.
shared uint run_entries[kSlices], run_wanted[kSlices], run_lit[kSlices], run_max[kSlices], run_over[kSlices];
shared uint run_dropped[kSlices], run_cut[kSlices], run_cut_entries[kSlices], run_lights[kSlices];

uvec3 froxel_texel(uint f) {
  return uvec3(f % tiles_x, (f / tiles_x) % tiles_y, f / (tiles_x * tiles_y));
}

void place_lists() {
  uint lane = gl_LocalInvocationID.x;
  uint total = tiles_x * tiles_y * kSlices;
  uint per_run = (total + kSlices - 1u) / kSlices;
  uint begin = min(lane * per_run, total), end = min(begin + per_run, total);
  uint capped = 0u, wanted = 0u, lit = 0u, longest = 0u, over = 0u, dropped = 0u;
  for (uint f = begin; f < end; ++f) {
    uint count = imageLoad(clusters, ivec3(froxel_texel(f))).y;
    capped = add_saturated(capped, min(count, max_per_froxel));
    wanted = add_saturated(wanted, count);
    longest = max(longest, count);
    if (count > 0u) ++lit;
    if (count > max_per_froxel) {
      ++over;
      dropped = add_saturated(dropped, count - max_per_froxel);
    }
  }
  run_entries[lane] = capped;
  barrier();
  uint start = 0u;
  for (uint k = 0u; k < lane; ++k) start = add_saturated(start, run_entries[k]);
  uint stored = 0u, cut = 0u, cut_entries = 0u;
  for (uint f = begin; f < end; ++f) {
    ivec3 texel = ivec3(froxel_texel(f));
    uint count = min(imageLoad(clusters, texel).y, max_per_froxel);
    uint at = min(start, max_indices);
    uint kept = min(count, max_indices - at);
    stored += kept;
    if (kept < count) {
      ++cut;
      cut_entries = add_saturated(cut_entries, count - kept);
    }
    imageStore(clusters, texel, uvec4(at, kept, 0u, 0u));
    start = add_saturated(start, count);
  }
  // Local lights, counted by the same invocations.
  uint local_lights = 0u;
  for (uint i = lane; i < frame.counts.x; i += kSlices)
    if (uint(lights[i].position_type.w) != kLightDirectional) ++local_lights;
  barrier();
  run_entries[lane] = stored;
  run_wanted[lane] = wanted;
  run_lit[lane] = lit;
  run_max[lane] = longest;
  run_over[lane] = over;
  run_dropped[lane] = dropped;
  run_cut[lane] = cut;
  run_cut_entries[lane] = cut_entries;
  run_lights[lane] = local_lights;
  barrier();
  if (lane != 0u) return;
  uint sums[9] = uint[9](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
  for (uint k = 0u; k < kSlices; ++k) {
    sums[0] += run_entries[k];
    sums[1] = add_saturated(sums[1], run_wanted[k]);
    sums[2] += run_lit[k];
    sums[3] = max(sums[3], run_max[k]);
    sums[4] += run_over[k];
    sums[5] = add_saturated(sums[5], run_dropped[k]);
    sums[6] += run_cut[k];
    sums[7] = add_saturated(sums[7], run_cut_entries[k]);
    sums[8] += run_lights[k];
  }
  stats.lights = sums[8];
  stats.froxels = total;
  stats.froxels_lit = sums[2];
  stats.entries = sums[0];
  stats.entries_wanted = sums[1];
  stats.max_count = sums[3];
  stats.froxels_over_cap = sums[4];
  stats.dropped_over_cap = sums[5];
  stats.froxels_cut = sums[6];
  stats.dropped_cut = sums[7];
  stats.per_froxel_cap = max_per_froxel;
  stats.index_capacity = max_indices;
  stats.max_distance = max_distance;
  stats.tile_size = kTile;
  stats.slices = kSlices;
}

// Phase 3, besides the lists: the entries past the last one are zero, so the buffer is defined.
void zero_tail() {
  uint groups = tiles_x * tiles_y;
  uint group = gl_WorkGroupID.y * tiles_x + gl_WorkGroupID.x;
  for (uint i = stats.entries + group * kSlices + gl_LocalInvocationID.x; i < indices.length(); i += groups * kSlices)
    indices[i] = 0u;
}

void main() {
  if (phase == 0u) {
    build_block_list();
  } else if (phase == 2u) {
    place_lists();
  } else {
    if (phase == 3u) zero_tail();
    build_lists();
  }
}
