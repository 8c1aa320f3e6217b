// lights.cluster (frame.md section 4): per froxel — a tile_size×tile_size-pixel tile × one of
// `slices` exponential depth slices (passes/lights/cluster_layout.h; 32 and 64 by default) — the
// list of frame.lights' local lights whose bound reaches it, built on the GPU from the light list
// and depth.pyramid's min/max depth per tile (cluster.comp states the test). Outputs:
// lights.clusters (offset and count per froxel), lights.cluster_indices (the lists, one after
// another) and lights.cluster_stats. A froxel keeps at most max_lights_per_froxel lights (those
// of lowest index) and all lists together at most max_indices; what the caps drop is counted in
// lights.cluster_stats and reported on stderr after the frame (warn_from). The lists are the
// same on every run (no order-dependent atomics), so every output compares exactly. Skipped when
// the scene has no local light.
#include <algorithm>
#include <bit>
#include <cstring>
#include <sstream>

#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"
#include "passes/lights/cluster_layout.h"
#include "passes/lights/stage.h"

namespace nightcap {
namespace {

// What the caps cut, in one line; "" when nothing was.
std::string overflow_warning(std::span<const uint8_t> bytes) {
  GpuClusterStats s{};
  if (bytes.size() < sizeof(s)) return "";
  std::memcpy(&s, bytes.data(), sizeof(s));
  std::ostringstream out;
  if (s.froxels_over_cap > 0)
    out << s.froxels_over_cap << " froxels over the cap of " << s.per_froxel_cap << " lights (the longest list "
        << s.max_count << "), " << s.dropped_over_cap << " entries dropped";
  if (s.froxels_cut > 0)
    out << (s.froxels_over_cap > 0 ? "; " : "") << s.froxels_cut << " froxels cut at the capacity of "
        << s.index_capacity << " entries, " << s.dropped_cut << " entries dropped";
  return out.str();
}

const KindRegistration kLightClusters({
    .kind = kinds::light_clusters,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["offset"] = t.codes.at(0);
          out["count"] = t.codes.at(1);
        },
    // The count, so a 1-light froxel shows.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          const double count = double(t.codes.at(1));
          const double grey = count / (count + 8);
          return TexelPicture{TexelPicture::Scale::display, {grey, grey, grey}};
        },
    .tiles = OutputTiles{"tile_size", kClusterTile},
    .lists = TexelLists{0, 1, "lights.cluster_indices", "lights"},
    .slices = DepthSlices{"depth.linear",
                          [](double metres, double znear, const std::map<std::string, double>& writer,
                             uint32_t slices) -> std::optional<uint32_t> {
                            const auto max_distance = writer.find("max_distance");
                            if (max_distance == writer.end()) return std::nullopt;
                            return cluster_slice(metres, znear, max_distance->second, slices);
                          }},
});

}  // namespace

BufferSchema cluster_stats_schema() { return NC_SCHEMA_OF(GpuClusterStats, NC_GPU_CLUSTER_STATS_FIELDS); }

BufferSchema cluster_index_schema() {
  struct Entry {
    uint32_t light;
  };
  return BufferSchema::of<Entry>().field("light", &Entry::light);
}

PassDecl lights_cluster_pass() {
  ImageDecl clusters{VK_FORMAT_R32G32_UINT, kinds::light_clusters};
  clusters.size.mode = SizeRule::Mode::output_tiles;
  clusters.size.tile_param = "tile_size";
  clusters.depth_param = "slices";
  return PassDecl("lights.cluster", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("frame.views", Use::uniform_buffer)
      .read("frame.lights", Use::storage_read)
      .read("depth.pyramid", Use::sampled)
      .write("lights.clusters", Use::storage_write, clusters)
      .write("lights.cluster_indices", Use::storage_write,
             BufferDecl{kinds::buffer, uint64_t(kClusterIndexCapacity) * 4})
      .write("lights.cluster_stats", Use::storage_write, BufferDecl{kinds::buffer, sizeof(GpuClusterStats)})
      .write("lights.cluster_blocks", Use::storage_write,
             BufferDecl{kinds::buffer, uint64_t(kClusterBlockCapacity) * 4})
      .layout("lights.cluster_indices", cluster_index_schema())
      .layout("lights.cluster_stats", cluster_stats_schema())
      .needs("local_lights")
      .choice("tile_size", kClusterTile, numbered_choices(kClusterTileSizes),
              "pixels on a side of a froxel's screen tile: 8, 16, 32 or 64")
      .param_int("slices", kClusterSlices, kClusterMinSlices, kClusterMaxSlices,
                 "exponential depth slices from the near plane to max_distance (a whole number)")
      .param_float("max_distance", 2000.0, 1.0, 1e6,
                   "metres where the last of the exponential depth slices starts; it reaches to infinity")
      .param_int("max_lights_per_froxel", 256, 1, 4096, "longest list a froxel keeps (the lights of lowest index)")
      .param_int("max_indices", kClusterIndexCapacity, 0, kClusterIndexCapacity,
                 "entries all lists together keep; froxels past it in froxel order (farthest slice last) are cut")
      .param_int("max_block_lights", kClusterBlockCapacity, 0, kClusterBlockCapacity,
                 "longest list a block of tiles keeps (also its share of lights.cluster_blocks); the tiles of a "
                 "block with more test every light: time, not the lists, depends on it")
      .warn_from("lights.cluster_stats", overflow_warning)
      .push_constants<ClusterConstants>()
      .shader("lights/cluster.comp")
      .run([](PassContext& ctx) {
        const int64_t tile_size = ctx.param_int("tile_size"), slices = ctx.param_int("slices");
        const ImageExtent tiles = ctx.desc("lights.clusters").extent;
        const uint32_t levels = ctx.desc("depth.pyramid").extent.mips;
        // Level 0 is half resolution: level L's texel covers 2^(L+1) pixels, a tile at
        // L = log2(tile_size) − 1.
        const uint32_t tile_level = std::bit_width(uint32_t(tile_size)) - 2;
        const ClusterConstants constants{uint32_t(ctx.param_int("max_lights_per_froxel")),
                                         uint32_t(ctx.param_int("max_indices")),
                                         int32_t(std::min(tile_level, levels - 1)),
                                         float(ctx.param_float("max_distance")),
                                         tiles.width,
                                         tiles.height,
                                         uint32_t(ctx.param_int("max_block_lights"))};
        // The shape as specialization constants: the slices are the workgroup (an invocation
        // each) and the tile a constant divisor, no loop bound read from memory. Each phase is
        // its own pipeline too: lavapipe runs every side of a branch, so a phase chosen by a push
        // constant would pay for the others' loops in every workgroup.
        const uint32_t blocks_x = group_count(tiles.width, kClusterBlock);
        const uint32_t blocks_y = group_count(tiles.height, kClusterBlock);
        for (int32_t phase = 0; phase < 4; ++phase) {
          ctx.bind_pipeline({int32_t(slices), int32_t(tile_size), phase});
          ctx.push_declared();
          ctx.push_constants(constants);
          if (phase == 0)
            vkCmdDispatch(ctx.cmd(), blocks_x, blocks_y, 1);
          else if (phase == 2)
            vkCmdDispatch(ctx.cmd(), 1, 1, 1);
          else
            vkCmdDispatch(ctx.cmd(), tiles.width, tiles.height, 1);
          if (phase < 3) ctx.storage_barrier();
        }
      });
}

}  // namespace nightcap
