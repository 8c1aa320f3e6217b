// lights.cluster against the CPU reference of tests/reference/cluster_reference.h, on the
// built-in city, the street shot of a 2 km map and synthetic scenes (many lights, a light at the
// camera, a light touching a surface, 10 000 lights in view). Bounds asserted:
// - Every froxel's list equals the reference's conservative list as a set, except for a light
//   whose reference margin (double precision) is within 2^-16 · (range + its farther end's
//   distance) of 0: the GPU's float arithmetic may put it on either side (its slice bounds come
//   from exp2 and log2 in float). Such edge differences are counted and printed.
// - No light that truly reaches a froxel (exact distance from its core to the frustum cell at
//   most its range) is missing from the froxel's list.
// - Marginal froxels, whose emptiness hangs on the rounding of a slice bound (one within 2^-16 of
//   the tile's opposite depth bound): the GPU finds each empty or thin. Each
//   light listed reaches the thin froxel (its range shrunk to the band's centre) within
//   2^-13 · scale; a light truly reaching the thin froxel is listed there when the froxel lists
//   anything, and otherwise in the neighbouring slice that shares the band (where the surfaces
//   are). Their share of the occupied froxels is printed and at most 0.1% (walls put on slice
//   bounds on purpose aside, where every occupied froxel is marginal).
// - Listed entries over truly reaching ones ≤ 1.5 on every scene (accuracy.md's target).
// - Lists are packed in froxel order, ascending, within the caps; lights.cluster_stats agrees
//   with them and records the froxels' shape; overflow is counted, cut where documented and
//   reported by the renderer.
// - All of this for other tile sizes and slice counts than frame.md's 32×32 × 64 too; values the
//   pass does not take are refused by name.
// (Over 600 lines: every case is lights.cluster against the one reference, sharing its tally.)
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <span>

#include <glm/gtc/matrix_transform.hpp>

#include "passes/depth/stage.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/gpu_types.h"
#include "passes/lights/cluster_layout.h"
#include "passes/lights/stage.h"
#include "tests/reference/cluster_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace ref = nightcap::reference;

// The most froxels whose emptiness hangs on a slice bound's rounding, as a share of the occupied.
const double kMarginalShare = 0.001;

// What lights.cluster read and wrote in one frame.
struct ClusterFrame {
  GpuFrameConstants frame{};
  GpuView camera{};
  std::vector<GpuLight> lights;
  std::shared_ptr<const std::vector<uint8_t>> pyramid, clusters;
  ImageExtent pyramid_extent, cluster_extent;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> blocks;  // lights.cluster_blocks
  GpuClusterStats stats{};
  // lights.cluster's parameters the frame ran with.
  double max_distance = 2000;
  uint32_t tile = kClusterTile, slices = kClusterSlices;

  std::pair<uint32_t, uint32_t> list(uint32_t tx, uint32_t ty, uint32_t slice) const {
    const size_t texel = (size_t(slice) * cluster_extent.height + ty) * cluster_extent.width + tx;
    uint32_t words[2];
    std::memcpy(words, clusters->data() + texel * 8, 8);
    return {words[0], words[1]};
  }
};

using Versions = std::map<std::string, std::pair<ResourceDesc, std::shared_ptr<const std::vector<uint8_t>>>>;

// `params`: lights.cluster's, defaults where not given.
ClusterFrame cluster_frame(const Versions& v, const ParamValues& params = {}) {
  const ParamValues all = resolve_params(lights_cluster_pass(), {{"lights.cluster", params}});
  ClusterFrame c;
  std::memcpy(&c.frame, v.at("frame.constants").second->data(), sizeof(c.frame));
  std::memcpy(&c.camera, v.at("frame.views").second->data(), sizeof(c.camera));
  c.lights = host_records<GpuLight>(*v.at("frame.lights").second);
  c.lights.resize(c.frame.counts.x);  // an empty list is a 16-byte buffer on the GPU
  c.pyramid = v.at("depth.pyramid").second;
  c.pyramid_extent = v.at("depth.pyramid").first.extent;
  c.clusters = v.at("lights.clusters").second;
  c.cluster_extent = v.at("lights.clusters").first.extent;
  c.indices = host_records<uint32_t>(*v.at("lights.cluster_indices").second);
  c.blocks = host_records<uint32_t>(*v.at("lights.cluster_blocks").second);
  std::memcpy(&c.stats, v.at("lights.cluster_stats").second->data(), sizeof(c.stats));
  c.max_distance = all.at("max_distance");
  c.tile = uint32_t(all.at("tile_size"));
  c.slices = uint32_t(all.at("slices"));
  return c;
}

const std::vector<std::string> kClusterOutputs = {"lights.clusters", "lights.cluster_indices", "lights.cluster_stats",
                                                  "lights.cluster_blocks"};

Versions frame_versions(const RenderedFrame& frame) {
  Versions v;
  for (const std::string& name : {std::string("frame.constants"), std::string("frame.views"),
                                  std::string("frame.lights"), std::string("depth.pyramid")})
    if (const VersionData* d = frame.execution.final_version(name)) v[name] = {d->desc, d->bytes};
  for (const std::string& name : kClusterOutputs)
    if (const VersionData* d = frame.execution.final_version(name)) v[name] = {d->desc, d->bytes};
  return v;
}

struct Comparison {
  uint64_t occupied = 0, marginal_froxels = 0, listed = 0, truly = 0;
  uint64_t marginal_truly = 0;  // light-froxel pairs truly reaching a marginal froxel's thin froxel
  uint64_t missing = 0, edge_differences = 0, differences = 0, malformed = 0;
  double worst_edge = 0;  // the largest |margin| / scale among edge differences
  std::string first_problem;
  double ratio() const { return truly ? double(listed) / double(truly) : 0.0; }
  double marginal_share() const { return occupied ? double(marginal_froxels) / double(occupied) : 0.0; }
  void problem(uint64_t& counter, const std::string& what) {
    if (counter++ == 0 && first_problem.empty()) first_problem = what;
  }
};

std::string froxel_name(uint32_t tx, uint32_t ty, uint32_t k) {
  return "froxel (" + std::to_string(tx) + ", " + std::to_string(ty) + ", slice " + std::to_string(k) + ")";
}

// A marginal froxel, which the GPU finds empty or thin (ref::thin_froxel) as it rounds a slice
// bound: either way each light it lists reaches the thin froxel within 2^-13 · scale. A light that
// truly reaches the thin froxel is listed in it when it lists anything (the GPU found it
// occupied); when it lists nothing, in the slice sharing its band, which holds the surfaces there.
void check_marginal(const ref::ClusterView& view, const std::vector<ref::LightCore>& cores, const ClusterFrame& c,
                    glm::uvec3 at, const ref::Froxel& f, std::span<const uint32_t> list, Comparison& result) {
  const ref::Froxel thin = ref::thin_froxel(f);
  const std::string name = froxel_name(at.x, at.y, at.z) + " (marginal)";
  for (uint32_t i : list) {
    if (i >= cores.size()) continue;  // malformed, counted by the caller
    const double margin = ref::conservative_margin(thin, cores[i]);
    if (margin < -0x1p-13 * cores[i].scale)
      result.problem(result.differences,
                     name + ": light " + std::to_string(i) + " listed, thin froxel's margin " + std::to_string(margin));
  }
  const uint32_t neighbour = ref::band_neighbour(view, f, at.z);
  const auto [offset, count] = c.list(at.x, at.y, neighbour);
  // A malformed neighbour list is counted where that froxel is compared.
  const bool use_own_list = !list.empty() || uint64_t(offset) + count > c.indices.size();
  const std::span<const uint32_t> holder =
      use_own_list ? list : std::span<const uint32_t>(c.indices.data() + offset, count);
  const ref::FroxelCell cell = ref::froxel_cell(thin);
  for (uint32_t i = 0; i < cores.size(); ++i)
    if (ref::truly_reaches(thin, cell, cores[i])) {
      ++result.marginal_truly;
      if (!std::binary_search(holder.begin(), holder.end(), i))
        result.problem(result.missing, name + ": light " + std::to_string(i) +
                                           " reaches it, listed neither there nor in " +
                                           froxel_name(at.x, at.y, neighbour));
    }
}

// Every froxel against the reference. Caps: the lists must be whole (the overflow test checks
// the caps on their own).
Comparison compare(const ClusterFrame& c, bool truly = true) {
  const ref::ClusterView view =
      ref::cluster_view(c.camera, *c.pyramid, c.pyramid_extent, c.max_distance, c.tile, c.slices);
  EXPECT_EQ(c.cluster_extent.width, view.tiles_x);
  EXPECT_EQ(c.cluster_extent.height, view.tiles_y);
  EXPECT_EQ(c.cluster_extent.depth, c.slices);
  std::vector<ref::LightCore> cores;
  for (const GpuLight& l : c.lights) cores.push_back(ref::light_core(view, l));
  Comparison result;
  uint32_t expected_offset = 0;
  std::vector<char> candidate(cores.size());
  for (uint32_t k = 0; k < c.slices; ++k)
    for (uint32_t ty = 0; ty < view.tiles_y; ++ty)
      for (uint32_t tx = 0; tx < view.tiles_x; ++tx) {
        const auto [offset, count] = c.list(tx, ty, k);
        const std::string name = froxel_name(tx, ty, k);
        if (offset != expected_offset || uint64_t(offset) + count > c.indices.size()) {
          result.problem(result.malformed, name + ": list at " + std::to_string(offset) + " (expected " +
                                               std::to_string(expected_offset) + ")");
          continue;
        }
        expected_offset += count;
        const std::span<const uint32_t> list(c.indices.data() + offset, count);
        if (!std::is_sorted(list.begin(), list.end()) || std::adjacent_find(list.begin(), list.end()) != list.end() ||
            (count > 0 && list.back() >= cores.size()))
          result.problem(result.malformed, name + ": not ascending indices of frame.lights");
        const ref::Froxel f = ref::froxel(view, tx, ty, k);
        result.occupied += f.occupied;
        if (f.marginal) {
          ++result.marginal_froxels;
          check_marginal(view, cores, c, {tx, ty, k}, f, list, result);
          continue;
        }
        result.listed += count;
        auto listed = [&](uint32_t i) { return std::binary_search(list.begin(), list.end(), i); };
        std::fill(candidate.begin(), candidate.end(), 0);
        for (uint32_t i = 0; i < cores.size(); ++i) {
          const ref::LightCore& core = cores[i];
          if (core.reach == ref::LightCore::Reach::bounded &&
              ref::point_segment_distance(glm::dvec3(0.5 * (f.lo + f.hi)), core.a, core.b) >
                  core.padded + 0.5 * glm::length(f.hi - f.lo) + 0x1p-16 * core.scale)
            continue;  // far from the froxel's box: the test's margin is below −2^-16 · scale
          candidate[i] = 1;
          const double margin = ref::conservative_margin(f, core);
          const bool expected = margin >= 0, got = listed(i);
          if (expected != got) {
            const double tolerance = 0x1p-16 * core.scale;
            if (std::isfinite(margin) && std::abs(margin) <= tolerance) {
              ++result.edge_differences;
              result.worst_edge = std::max(result.worst_edge, std::abs(margin) / core.scale);
            } else {
              result.problem(result.differences, name + ": light " + std::to_string(i) +
                                                     (got ? " listed" : " not listed") + ", reference margin " +
                                                     std::to_string(margin) + " m");
            }
          }
        }
        for (uint32_t i : list)
          if (i < cores.size() && !candidate[i])
            result.problem(result.differences, name + ": light " + std::to_string(i) + " listed, far from the froxel");
        if (!truly || !f.occupied) continue;
        const ref::FroxelCell cell = ref::froxel_cell(f);
        for (uint32_t i = 0; i < cores.size(); ++i)
          if (candidate[i] && ref::truly_reaches(f, cell, cores[i])) {
            ++result.truly;
            if (!listed(i)) result.problem(result.missing, name + ": light " + std::to_string(i) + " reaches it");
          }
      }
  return result;
}

// Stats against the lists they describe.
void check_stats(const ClusterFrame& c) {
  const GpuClusterStats& s = c.stats;
  uint64_t entries = 0, lit_stored = 0, longest_stored = 0;
  for (uint32_t k = 0; k < c.slices; ++k)
    for (uint32_t ty = 0; ty < c.cluster_extent.height; ++ty)
      for (uint32_t tx = 0; tx < c.cluster_extent.width; ++tx) {
        const uint32_t count = c.list(tx, ty, k).second;
        entries += count;
        lit_stored += count > 0;
        longest_stored = std::max<uint64_t>(longest_stored, count);
        EXPECT_LE(count, s.per_froxel_cap);
      }
  uint32_t local = 0;
  for (const GpuLight& l : c.lights) local += uint32_t(l.position_type.w) != uint32_t(LightType::directional);
  EXPECT_EQ(s.lights, local);
  EXPECT_EQ(s.froxels, c.cluster_extent.width * c.cluster_extent.height * c.slices);
  EXPECT_EQ(s.tile_size, c.tile);
  EXPECT_EQ(s.slices, c.slices);
  EXPECT_EQ(s.max_distance, float(c.max_distance));
  EXPECT_EQ(s.entries, entries);
  EXPECT_LE(s.entries, s.index_capacity);
  EXPECT_EQ(uint64_t(s.entries) + s.dropped_over_cap + s.dropped_cut, s.entries_wanted);
  EXPECT_GE(s.froxels_lit, lit_stored);
  EXPECT_GE(s.max_count, longest_stored);
  EXPECT_EQ(s.froxels_over_cap > 0, s.dropped_over_cap > 0);
  EXPECT_EQ(s.froxels_cut > 0, s.dropped_cut > 0);
  // The index buffer is defined past the last entry: zero.
  for (size_t i = s.entries; i < c.indices.size(); ++i)
    if (c.indices[i] != 0) {
      ADD_FAILURE() << "index entry " << i << " past the last list is " << c.indices[i];
      break;
    }
}

void report(const char* scene, const ClusterFrame& c, const Comparison& r) {
  std::printf(
      "%s: %zu lights, %llu occupied froxels, %u lit; %llu entries listed, %llu truly reaching (ratio %.3f, mean "
      "list %.2f over lit froxels, longest %u); %llu edge differences (worst margin %.2g of scale); %llu marginal "
      "froxels, %.4f%% of the occupied, %llu light-froxel pairs truly reaching them\n",
      scene, c.lights.size(), (unsigned long long)r.occupied, c.stats.froxels_lit, (unsigned long long)r.listed,
      (unsigned long long)r.truly, r.ratio(), c.stats.froxels_lit ? double(c.stats.entries) / c.stats.froxels_lit : 0.0,
      c.stats.max_count, (unsigned long long)r.edge_differences, r.worst_edge, (unsigned long long)r.marginal_froxels,
      100 * r.marginal_share(), (unsigned long long)r.marginal_truly);
}

// `marginal_share`: the most marginal froxels the scene may have, as a share of the occupied.
Comparison expect_matches_reference(const char* scene, const ClusterFrame& c, double marginal_share = kMarginalShare) {
  check_stats(c);
  EXPECT_EQ(c.stats.froxels_over_cap, 0u) << "the comparison needs whole lists";
  EXPECT_EQ(c.stats.froxels_cut, 0u) << "the comparison needs whole lists";
  const Comparison r = compare(c);
  report(scene, c, r);
  EXPECT_EQ(r.malformed, 0u) << r.first_problem;
  EXPECT_EQ(r.differences, 0u) << r.first_problem;
  EXPECT_EQ(r.missing, 0u) << r.first_problem;
  EXPECT_GT(r.truly, 0u) << "the scene must light something";
  EXPECT_LE(r.ratio(), 1.5);
  EXPECT_LE(r.marginal_share(), marginal_share);
  return r;
}

// A frame rendered only as far as lights.cluster (lighting is what takes long).
RenderSettings cluster_settings(uint32_t width, uint32_t height) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = kClusterOutputs;
  return settings;
}

// A synthetic view: the camera at the origin looking down −z (view = world), depth.linear given
// per pixel, the lights given in view space.
struct Synthetic {
  uint32_t width = 640, height = 360;
  double yfov = 0.9, znear = 0.1;
  std::vector<float> depth;
  std::vector<GpuLight> lights;
};

GpuLight point_light(glm::vec3 p, float range) {
  GpuLight l{};
  l.position_type = glm::vec4(p, float(LightType::point));
  l.end_radius = glm::vec4(p, 0.05f);
  l.color_range = glm::vec4(1, 1, 1, range);
  return l;
}

GpuLight tube_light(glm::vec3 a, glm::vec3 b, float range) {
  GpuLight l = point_light(a, range);
  l.position_type.w = float(LightType::tube);
  l.end_radius = glm::vec4(b, 0.02f);
  return l;
}

class LightsCluster : public GpuTest {
 protected:
  static ClusterFrame run_synthetic(const Synthetic& s, ParamValues params = {}) {
    std::vector<uint8_t> depth_bytes(s.depth.size() * 4);
    std::memcpy(depth_bytes.data(), s.depth.data(), depth_bytes.size());
    const IsolatedRun pyramid =
        run(depth_pyramid_pass(),
            {{"depth.linear", image(VK_FORMAT_R32_SFLOAT, kinds::linear_depth, s.width, s.height, depth_bytes)}},
            s.width, s.height);
    GpuView camera{};
    const double aspect = double(s.width) / s.height;
    camera.view = glm::mat4(1.0f);
    camera.projection = glm::mat4(reversed_z_projection(s.yfov, aspect, s.znear));
    camera.view_projection = camera.projection;
    camera.viewport = {float(s.width), float(s.height), 1.0f / s.width, 1.0f / s.height};
    camera.projection_params = {float(s.znear), float(s.yfov), float(aspect), 0};
    GpuFrameConstants frame{};
    frame.counts = {uint32_t(s.lights.size()), 0, 0, 0};
    std::map<std::string, IsolatedInput> inputs;
    inputs["frame.constants"] = record_input(frame);
    inputs["frame.views"] = record_input(camera);
    inputs["frame.lights"] = records_input<GpuLight>(s.lights);
    inputs["depth.pyramid"] = {pyramid.output_descs.at("depth.pyramid"), pyramid.outputs.at("depth.pyramid")};
    const IsolatedRun result = run(lights_cluster_pass(), inputs, s.width, s.height, params);
    EXPECT_EQ(first_non_finite(result.execution), "");
    Versions v;
    for (const auto& [name, in] : inputs) v[name] = {in.desc, in.bytes};
    for (const std::string& name : kClusterOutputs) v[name] = {result.output_descs.at(name), result.outputs.at(name)};
    return cluster_frame(v, params);
  }
};

TEST_F(LightsCluster, CityMatchesTheReference) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  Renderer renderer(*gpu_, scene, cluster_settings(1280, 720));
  const RenderedFrame frame = renderer.render_frame(0, true);
  EXPECT_TRUE(frame.warnings.empty());
  expect_matches_reference("city", cluster_frame(frame_versions(frame)));
}

TEST_F(LightsCluster, MapStreetShotMatchesTheReference) {
  const Scene scene = build_map({1, 2.0, Shot::street});
  Renderer renderer(*gpu_, scene, cluster_settings(1280, 720));
  const RenderedFrame frame = renderer.render_frame(0, true);
  EXPECT_TRUE(frame.warnings.empty());
  const ClusterFrame c = cluster_frame(frame_versions(frame));
  EXPECT_GT(c.lights.size(), 100u) << "a street of the map keeps many lights in view";
  expect_matches_reference("2 km map, street shot", c);
}

// Random depths per 8×8 block (some sky), and lights of every kind around the view: points,
// spots, tubes (some through the camera's plane), one of infinite range and a directional one.
Synthetic many_lights() {
  Synthetic s;
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  s.depth.resize(size_t(s.width) * s.height);
  for (uint32_t y = 0; y < s.height; ++y)
    for (uint32_t x = 0; x < s.width; ++x) {
      std::mt19937 block(uint32_t((y / 8) * 1000 + x / 8));
      const float r = std::uniform_real_distribution<float>(0.0f, 1.0f)(block);
      s.depth[size_t(y) * s.width + x] = r < 0.1f ? 1e6f : 0.5f + 300.0f * r * r;
    }
  for (int i = 0; i < 2000; ++i) {
    const float d = 0.2f + 400.0f * unit(rng) * unit(rng);
    const glm::vec3 p((unit(rng) * 2 - 1) * d, (unit(rng) * 2 - 1) * d * 0.6f, -d + 5.0f * (unit(rng) - 0.5f));
    const float range = 0.5f + 30.0f * unit(rng) * unit(rng);
    if (i % 5 == 3) {
      s.lights.push_back(tube_light(p, p + glm::vec3(6 * unit(rng) - 3, 4 * unit(rng) - 2, 6 * unit(rng) - 3), range));
    } else {
      s.lights.push_back(point_light(p, range));
      if (i % 5 == 1) s.lights.back().position_type.w = float(LightType::spot);
    }
  }
  s.lights.push_back(point_light({3, 1, -20}, 0.0f));  // range 0: reaches everything
  GpuLight sun = point_light({0, 0, 0}, 0.0f);
  sun.position_type.w = float(LightType::directional);
  s.lights.push_back(sun);
  return s;
}

TEST_F(LightsCluster, ManyLightsMatchTheReference) {
  const ClusterFrame c = run_synthetic(many_lights());
  expect_matches_reference("2000 synthetic lights", c);
  EXPECT_EQ(c.stats.lights, 2001u);
}

// Walls on slice bounds: tile by tile, the surfaces lie at the start of one slice (8 to 55), as
// the reference computes it, rounded to float. Both froxels that meet there are marginal, and
// the GPU finds one or both occupied as its exp2 rounds. 300 lights about the walls, and one of
// range 0, listed wherever the GPU finds a froxel occupied.
Synthetic walls_on_slice_bounds() {
  Synthetic s;
  const uint32_t tiles_x = (s.width + kClusterTile - 1) / kClusterTile;
  s.depth.resize(size_t(s.width) * s.height);
  for (uint32_t y = 0; y < s.height; ++y)
    for (uint32_t x = 0; x < s.width; ++x) {
      const uint32_t slice = 8 + ((y / kClusterTile) * tiles_x + x / kClusterTile) % 48;
      s.depth[size_t(y) * s.width + x] = float(s.znear * std::pow(2000.0 / s.znear, double(slice) / kClusterSlices));
    }
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float half_height = std::tan(float(s.yfov) / 2), half_width = half_height * s.width / s.height;
  for (int i = 0; i < 300; ++i) {
    const float wall = s.depth[size_t(unit(rng) * (s.height - 1)) * s.width + size_t(unit(rng) * (s.width - 1))];
    const float d = wall * (0.8f + 0.4f * unit(rng));
    const glm::vec3 p((unit(rng) * 2 - 1) * d * half_width, (unit(rng) * 2 - 1) * d * half_height, -d);
    s.lights.push_back(point_light(p, 0.5f + 0.3f * wall * unit(rng)));
  }
  s.lights.push_back(point_light({0, 0, -5}, 0.0f));
  return s;
}

TEST_F(LightsCluster, WallsOnSliceBoundsMatchTheReference) {
  const Synthetic s = walls_on_slice_bounds();
  const ClusterFrame c = run_synthetic(s);
  // Every occupied froxel is marginal here.
  const Comparison r = expect_matches_reference("walls on slice bounds", c, 1.0);
  EXPECT_EQ(r.marginal_froxels, 2 * c.cluster_extent.width * c.cluster_extent.height);
  EXPECT_GT(r.marginal_truly, 0u);
}

// lights.cluster_blocks, as cluster.comp lays it out: per block of kClusterBlock² tiles, a slot of
// equal size holding the count (or kOverflow) and the block's list.
struct BlockLists {
  static constexpr uint32_t kOverflow = 0xffffffffu;
  uint32_t blocks_x, blocks_y, slot;
  const std::vector<uint32_t>& words;
  BlockLists(const ClusterFrame& c)
      : blocks_x((c.cluster_extent.width + kClusterBlock - 1) / kClusterBlock),
        blocks_y((c.cluster_extent.height + kClusterBlock - 1) / kClusterBlock),
        slot(uint32_t(c.blocks.size()) / (blocks_x * blocks_y)),
        words(c.blocks) {}
  uint32_t count(uint32_t bx, uint32_t by) const { return words[(by * blocks_x + bx) * slot]; }
  std::span<const uint32_t> list(uint32_t bx, uint32_t by) const {
    return {words.data() + (by * blocks_x + bx) * slot + 1, count(bx, by)};
  }
};

// The lists a tile's froxels hold are drawn from its block's (so a block's test drops no light any
// of its froxels keeps), each block list ascends, and what a slot does not use is zero. Returns
// the mean length of a block's list.
double expect_block_lists_cover_their_froxels(const ClusterFrame& c) {
  const BlockLists blocks(c);
  EXPECT_GE(blocks.slot, 2u);
  uint64_t block_entries = 0;
  for (uint32_t by = 0; by < blocks.blocks_y; ++by)
    for (uint32_t bx = 0; bx < blocks.blocks_x; ++bx) {
      const std::string block = "block (" + std::to_string(bx) + ", " + std::to_string(by) + ")";
      if (blocks.count(bx, by) == BlockLists::kOverflow) {
        ADD_FAILURE() << block << " overflowed its slot of " << blocks.slot << " words";
        continue;
      }
      const std::span<const uint32_t> list = blocks.list(bx, by);
      EXPECT_TRUE(std::is_sorted(list.begin(), list.end()) &&
                  std::adjacent_find(list.begin(), list.end()) == list.end())
          << block;
      block_entries += list.size();
      const auto unused = c.blocks.begin() + (by * blocks.blocks_x + bx) * blocks.slot + 1 + list.size();
      EXPECT_TRUE(std::all_of(unused, unused + (blocks.slot - 1 - list.size()), [](uint32_t w) { return w == 0; }))
          << block;
      for (uint32_t ty = by * kClusterBlock; ty < std::min((by + 1) * kClusterBlock, c.cluster_extent.height); ++ty)
        for (uint32_t tx = bx * kClusterBlock; tx < std::min((bx + 1) * kClusterBlock, c.cluster_extent.width); ++tx)
          for (uint32_t k = 0; k < c.slices; ++k) {
            const auto [offset, count] = c.list(tx, ty, k);
            for (uint32_t e = offset; e < offset + count; ++e)
              if (!std::binary_search(list.begin(), list.end(), c.indices[e])) {
                ADD_FAILURE() << froxel_name(tx, ty, k) << " lists light " << c.indices[e] << ", " << block
                              << " does not";
                return 0;
              }
          }
    }
  EXPECT_TRUE(std::all_of(c.blocks.begin() + blocks.blocks_x * blocks.blocks_y * blocks.slot, c.blocks.end(),
                          [](uint32_t w) { return w == 0; }));
  return double(block_entries) / (blocks.blocks_x * blocks.blocks_y);
}

TEST_F(LightsCluster, BlockListsHoldEveryLightTheirFroxelsList) {
  // Random depths with sky in every block: each block's box spans the whole view's depth.
  const ClusterFrame synthetic = run_synthetic(many_lights());
  const double synthetic_mean = expect_block_lists_cover_their_froxels(synthetic);
  // A street of the map, where what the blocks are for shows: most lights miss most blocks.
  const Scene scene = build_map({1, 2.0, Shot::street});
  Renderer renderer(*gpu_, scene, cluster_settings(1280, 720));
  const ClusterFrame street = cluster_frame(frame_versions(renderer.render_frame(0, true)));
  const double street_mean = expect_block_lists_cover_their_froxels(street);
  std::printf("a block lists %.1f of 2002 synthetic lights; %.1f of the street's %zu\n", synthetic_mean, street_mean,
              street.lights.size());
  EXPECT_LT(street_mean, 0.25 * double(street.lights.size()));
}

// A block whose list does not fit is marked, and its tiles test every light: the lists stay the
// reference's.
TEST_F(LightsCluster, BlocksThatOverflowTestEveryLight) {
  const Synthetic s = many_lights();
  // A cap at the median of the lists' lengths: about half the blocks overflow.
  const ClusterFrame uncapped = run_synthetic(s);
  const BlockLists uncapped_blocks(uncapped);
  std::vector<uint32_t> counts;
  for (uint32_t by = 0; by < uncapped_blocks.blocks_y; ++by)
    for (uint32_t bx = 0; bx < uncapped_blocks.blocks_x; ++bx) counts.push_back(uncapped_blocks.count(bx, by));
  std::sort(counts.begin(), counts.end());
  const uint32_t cap = counts[counts.size() / 2];
  const ClusterFrame c = run_synthetic(s, {{"max_block_lights", cap}});
  const BlockLists blocks(c);
  uint32_t overflowed = 0;
  for (uint32_t by = 0; by < blocks.blocks_y; ++by)
    for (uint32_t bx = 0; bx < blocks.blocks_x; ++bx) {
      const uint32_t count = blocks.count(bx, by);
      if (count == BlockLists::kOverflow)
        ++overflowed;
      else
        EXPECT_EQ(count, uncapped_blocks.count(bx, by));
    }
  EXPECT_GT(overflowed, 0u);
  EXPECT_LT(overflowed, blocks.blocks_x * blocks.blocks_y) << "some blocks keep their lists";
  EXPECT_EQ(c.indices, uncapped.indices);
  expect_matches_reference(("2000 synthetic lights, blocks of at most " + std::to_string(cap) + " lights").c_str(), c);
}

// Shapes other than frame.md's 32×32 × 64: finer and coarser tiles, fewer and more slices.
const std::vector<ParamValues> kOtherShapes = {
    {{"tile_size", 16}, {"slices", 32}}, {{"tile_size", 64}, {"slices", 128}}, {{"tile_size", 8}, {"slices", 16}}};

std::string shape_name(const char* scene, const ParamValues& shape) {
  return std::string(scene) + ", tiles of " + std::to_string(int(shape.at("tile_size"))) + " px, " +
         std::to_string(int(shape.at("slices"))) + " slices";
}

TEST_F(LightsCluster, ManyLightsMatchTheReferenceInOtherShapes) {
  const Synthetic s = many_lights();
  for (const ParamValues& shape : kOtherShapes) {
    SCOPED_TRACE(shape_name("2000 synthetic lights", shape));
    const ClusterFrame c = run_synthetic(s, shape);
    EXPECT_EQ(c.cluster_extent.width, (s.width + c.tile - 1) / c.tile);
    EXPECT_EQ(c.cluster_extent.depth, c.slices);
    expect_matches_reference(shape_name("2000 synthetic lights", shape).c_str(), c);
  }
}

TEST_F(LightsCluster, MapStreetShotMatchesTheReferenceInOtherShapes) {
  const Scene scene = build_map({1, 2.0, Shot::street});
  for (const ParamValues& shape : {kOtherShapes[0], kOtherShapes[1]}) {
    SCOPED_TRACE(shape_name("2 km map, street shot", shape));
    RenderSettings settings = cluster_settings(1280, 720);
    settings.params["lights.cluster"] = shape;
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    EXPECT_TRUE(frame.warnings.empty());
    expect_matches_reference(shape_name("2 km map, street shot", shape).c_str(),
                             cluster_frame(frame_versions(frame), shape));
  }
}

// tile_size and slices take what the pass can run: another value is refused by name, not rounded.
TEST_F(LightsCluster, ShapesItCannotRunAreRefused) {
  Synthetic s;
  s.width = 64;
  s.height = 36;
  s.depth.assign(size_t(s.width) * s.height, 3.0f);
  s.lights = {point_light({0, 0, -3}, 2.0f)};
  const std::pair<ParamValues, std::string> refused[] = {
      {{{"tile_size", 24}}, "lights.cluster.tile_size = 24: enum parameter, expected one of 8, 16, 32, 64"},
      {{{"tile_size", 128}}, "lights.cluster.tile_size = 128: enum parameter, expected one of 8, 16, 32, 64"},
      {{{"slices", 8}}, "lights.cluster.slices = 8: int parameter, expected a whole number in [16, 128]"},
      {{{"slices", 129}}, "lights.cluster.slices = 129: int parameter, expected a whole number in [16, 128]"},
      {{{"slices", 20.5}}, "lights.cluster.slices = 20.5: int parameter, expected a whole number in [16, 128]"},
  };
  for (const auto& [params, message] : refused) {
    try {
      run_synthetic(s, params);
      ADD_FAILURE() << message << ": accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

// A point light at the camera and a tube through it, before a wall 3 m away: every tile's
// froxel on the wall lists both.
TEST_F(LightsCluster, LightAtTheCamera) {
  Synthetic s;
  s.depth.assign(size_t(s.width) * s.height, 3.0f);
  s.lights = {point_light({0, 0, 0}, 5.0f), tube_light({-1, 0, 1}, {1, 0, -1}, 5.0f)};
  const ClusterFrame c = run_synthetic(s);
  expect_matches_reference("lights at the camera", c);
  const uint32_t slice = cluster_slice(3.0, s.znear, 2000.0);
  for (uint32_t ty = 0; ty < c.cluster_extent.height; ++ty)
    for (uint32_t tx = 0; tx < c.cluster_extent.width; ++tx) {
      const auto [offset, count] = c.list(tx, ty, slice);
      ASSERT_EQ(count, 2u) << froxel_name(tx, ty, slice);
      EXPECT_EQ(c.indices[offset], 0u);
      EXPECT_EQ(c.indices[offset + 1], 1u);
      for (uint32_t k = 0; k < c.slices; ++k) {
        if (k == slice) continue;
        EXPECT_EQ(c.list(tx, ty, k).second, 0u) << froxel_name(tx, ty, k) << " has no surface";
      }
    }
}

// A wall 10 m ahead; a light 2 m in front of it with a 2 m range touches it on the view axis, one
// 1 cm farther does not reach it (the padding, 2^-12 · (2 + 8) m ≈ 2.4 mm, does not cover 1 cm).
TEST_F(LightsCluster, LightTouchingASurface) {
  Synthetic s;
  s.depth.assign(size_t(s.width) * s.height, 10.0f);
  s.lights = {point_light({0, 0, -8}, 2.0f), point_light({0, 0, -7.99f}, 2.0f)};
  const ClusterFrame c = run_synthetic(s);
  expect_matches_reference("a light touching a wall", c);
  // The view axis (pixel 320, 180) lies on the edge between tiles 9 and 10 of row 5.
  const uint32_t slice = cluster_slice(10.0, s.znear, 2000.0);
  for (uint32_t tx : {9u, 10u}) {
    const auto [offset, count] = c.list(tx, 5, slice);
    ASSERT_EQ(count, 1u) << froxel_name(tx, 5, slice);
    EXPECT_EQ(c.indices[offset], 0u) << "the touching light";
  }
  EXPECT_EQ(c.stats.entries, 2u) << "the touching light in the two froxels on the axis, nothing else";
}

// 10 000 small lights in view overflow both caps: counted, cut as documented, no crash. Each
// list is the first lights (lowest indices) of the reference's, and froxels lose entries to the
// index capacity only after every earlier froxel (in froxel order) kept its own. Marginal froxels
// the GPU found occupied count as their thin froxels; those it found empty are passed over.
TEST_F(LightsCluster, TenThousandLightsOverflowIsCountedNotSilent) {
  Synthetic s;
  s.width = 1280;
  s.height = 720;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  s.depth.resize(size_t(s.width) * s.height);
  for (uint32_t y = 0; y < s.height; ++y)
    for (uint32_t x = 0; x < s.width; ++x) s.depth[size_t(y) * s.width + x] = 5.0f + 0.3f * float(x % 97 + y % 89);
  for (int i = 0; i < 10000; ++i) {
    const float d = 2.0f + 60.0f * unit(rng);
    s.lights.push_back(
        point_light({(unit(rng) * 2 - 1) * d * 0.8f, (unit(rng) * 2 - 1) * d * 0.45f, -d}, 1.0f + 6.0f * unit(rng)));
  }
  const uint32_t cap = 64, capacity = 200000;
  const ClusterFrame c = run_synthetic(s, {{"max_lights_per_froxel", double(cap)}, {"max_indices", double(capacity)}});
  check_stats(c);
  const GpuClusterStats& st = c.stats;
  std::printf(
      "10 000 lights: %u froxels over the cap of %u (%u entries dropped, longest %u), %u cut at %u entries "
      "(%u dropped); %u stored of %u wanted\n",
      st.froxels_over_cap, cap, st.dropped_over_cap, st.max_count, st.froxels_cut, capacity, st.dropped_cut, st.entries,
      st.entries_wanted);
  EXPECT_GT(st.froxels_over_cap, 0u);
  EXPECT_GT(st.froxels_cut, 0u);
  EXPECT_EQ(st.entries, capacity);
  EXPECT_EQ(st.per_froxel_cap, cap);
  EXPECT_EQ(st.index_capacity, capacity);
  EXPECT_NE(st.entries_wanted, 0xffffffffu) << "no sum saturated";

  // Each list against the reference: a prefix of its conservative list (edge lights aside).
  const ref::ClusterView view = ref::cluster_view(c.camera, *c.pyramid, c.pyramid_extent, c.max_distance);
  std::vector<ref::LightCore> cores;
  for (const GpuLight& l : c.lights) cores.push_back(ref::light_core(view, l));
  bool cut_seen = false;
  uint64_t checked = 0, edge = 0, marginal = 0;
  for (uint32_t k = 0; k < c.slices; ++k)
    for (uint32_t ty = 0; ty < view.tiles_y; ++ty)
      for (uint32_t tx = 0; tx < view.tiles_x; ++tx) {
        const auto [offset, count] = c.list(tx, ty, k);
        const ref::Froxel f = ref::froxel(view, tx, ty, k);
        const std::string name = froxel_name(tx, ty, k);
        if (!f.marginal && !f.occupied) {
          ASSERT_EQ(count, 0u) << name << " holds no surface";
          continue;
        }
        // A marginal froxel the GPU found empty says nothing about the caps; one it found occupied
        // is its thin froxel, within check_marginal's tolerance.
        if (f.marginal && count == 0) continue;
        const ref::Froxel tested = f.marginal ? ref::thin_froxel(f) : f;
        const double tolerance = f.marginal ? 0x1p-13 : 0x1p-16;  // of the light's scale
        marginal += f.marginal;
        std::vector<uint32_t> sure, either;  // listed by the reference; within the edge tolerance
        const glm::dvec3 centre = 0.5 * (tested.lo + tested.hi);
        const double half_diagonal = 0.5 * glm::length(tested.hi - tested.lo);
        for (uint32_t i = 0; i < cores.size(); ++i) {
          if (ref::point_segment_distance(centre, cores[i].a, cores[i].b) >
              cores[i].padded + half_diagonal + tolerance * cores[i].scale)
            continue;  // the margin is below −tolerance · scale
          const double margin = ref::conservative_margin(tested, cores[i]);
          if (std::abs(margin) <= tolerance * cores[i].scale)
            either.push_back(i);
          else if (margin > 0)
            sure.push_back(i);
        }
        edge += either.size();
        const std::span<const uint32_t> list(c.indices.data() + offset, count);
        ASSERT_TRUE(std::is_sorted(list.begin(), list.end())) << name;
        for (uint32_t i : list)
          ASSERT_TRUE(std::binary_search(sure.begin(), sure.end(), i) ||
                      std::binary_search(either.begin(), either.end(), i))
              << name << ": light " << i << " listed";
        // Every sure light below the last kept index is kept; a froxel not cut keeps min(cap, all).
        const uint32_t last = count ? list.back() : 0;
        for (uint32_t i : sure) {
          if (!count || i >= last) continue;
          ASSERT_TRUE(std::binary_search(list.begin(), list.end(), i)) << name << " lost " << i;
        }
        // Not cut, a froxel keeps at least min(cap, sure); the first that keeps less was cut,
        // and every froxel after it in froxel order keeps nothing.
        const size_t whole = std::min<size_t>(cap, sure.size());
        if (cut_seen) {
          ASSERT_EQ(count, 0u) << name << " kept entries after an earlier froxel was cut";
        } else if (count < whole) {
          cut_seen = true;
        } else if (either.empty()) {
          ASSERT_EQ(count, whole) << name;
        }
        ++checked;
      }
  EXPECT_TRUE(cut_seen);
  std::printf("checked %llu froxels (%llu marginal); %llu light-froxel pairs on the edge\n",
              (unsigned long long)checked, (unsigned long long)marginal, (unsigned long long)edge);
}

// Caps that cut are reported after the frame on stderr (and in RenderedFrame::warnings).
TEST_F(LightsCluster, OverflowIsReportedByTheRenderer) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings = cluster_settings(320, 180);
  settings.params["lights.cluster"] = {{"max_lights_per_froxel", 1.0}, {"max_indices", 50.0}};
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  ASSERT_EQ(frame.warnings.size(), 1u);
  EXPECT_NE(frame.warnings[0].find("lights.cluster: "), std::string::npos) << frame.warnings[0];
  EXPECT_NE(frame.warnings[0].find("over the cap of 1 lights"), std::string::npos) << frame.warnings[0];
  EXPECT_NE(frame.warnings[0].find("cut at the capacity of 50 entries"), std::string::npos) << frame.warnings[0];
  const ClusterFrame c = cluster_frame(frame_versions(frame), settings.params.at("lights.cluster"));
  check_stats(c);
  EXPECT_EQ(c.stats.entries, 50u);
}

// No local light: skipped, and the pass's outputs hold their clear value (no list).
TEST_F(LightsCluster, SkippedWithoutLocalLights) {
  Scene scene;
  Light sun;
  sun.type = LightType::directional;
  sun.direction = {0, -1, 0};
  scene.lights.push_back(sun);
  Renderer renderer(*gpu_, scene, cluster_settings(64, 64));
  const RenderedFrame frame = renderer.render_frame(0, true);
  bool found = false;
  for (const CompiledPass& p : frame.graph.passes)
    if (p.decl->name == "lights.cluster") {
      found = true;
      EXPECT_FALSE(p.runs);
      EXPECT_EQ(p.reason, "scene has no local_lights");
    }
  EXPECT_TRUE(found);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
