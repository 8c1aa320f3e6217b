// How lights.cluster divides the view and lays out its lists, for the pass, its shader
// (passes/lights/cluster.comp), the debugger and the tests. A froxel is a T×T-pixel screen tile
// times one of S depth slices spaced exponentially from the near plane to `max_distance`, the
// last slice reaching to infinity (T, S and max_distance are lights.cluster's parameters
// tile_size, slices and max_distance; frame.md's defaults are 32 and 64):
//   slice k covers linear depth [z_k, z_(k+1)), z_k = znear · (far / znear)^(k / S),
//   far = max(max_distance, 2 · znear), z_0 = 0 and z_S = ∞ (nothing lies nearer than znear).
// lights.clusters (R32G32_UINT, tiles_x × tiles_y × S) holds each froxel's (offset, count) into
// lights.cluster_indices, whose entries are indices into frame.lights, ascending in each froxel.
// lights.cluster_stats records T, S and max_distance, so that whoever reads the lists (lighting,
// replay, the debugger) finds a pixel's froxel from the capture alone.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "passes/core/buffer_schema.h"
#include "passes/core/resource_kind.h"
#include "passes/lights/cluster_layout.glsl.h"

namespace nightcap {

namespace kinds {
// Per froxel, the offset and length of its list in lights.cluster_indices (registered beside
// lights.cluster, with the tiles, lists and slices that `inspect` follows).
inline constexpr ResourceKind light_clusters{"light_clusters"};
}  // namespace kinds

constexpr uint32_t kClusterTile = 32;    // tile_size's default: pixels on a side of a tile
constexpr uint32_t kClusterSlices = 64;  // slices' default: depth slices
// What tile_size and slices may be: a tile is a whole level of depth.pyramid (a power of two of
// 8 or more pixels); the slices are one workgroup (an invocation each).
constexpr uint32_t kClusterTileSizes[] = {8, 16, 32, 64};
constexpr uint32_t kClusterMinSlices = 16, kClusterMaxSlices = 128;
// Entries lights.cluster_indices holds (4 MiB): about 18 per froxel at 1280×720, 2 at 3840×2160.
constexpr uint32_t kClusterIndexCapacity = 1u << 20;
// Words of lights.cluster_blocks (4 MiB), shared equally by the blocks: 17 475 lights a block at
// 1280×720 with 32-pixel tiles; a block whose list is longer makes its tiles test every light.
constexpr uint32_t kClusterBlockCapacity = 1u << 20;

static_assert(sizeof(GpuClusterStats) == 60);

BufferSchema cluster_stats_schema();
BufferSchema cluster_index_schema();

// The slice of a linear depth (metres), as lighting finds a pixel's froxel.
inline uint32_t cluster_slice(double depth, double znear, double max_distance, uint32_t slices = kClusterSlices) {
  const double far = std::max(max_distance, 2.0 * znear);
  const double k = std::floor(std::log2(depth / znear) / std::log2(far / znear) * slices);
  return uint32_t(std::clamp(k, 0.0, double(slices - 1)));
}

}  // namespace nightcap
