// shadow.cull (CPU): the sun's cascades for this frame and what each draws. frame.md's
// shadow.cascades culls "per cascade against an up-to-8-plane convex volume"; culling is CPU
// work, and a CPU pass is how the graph records it, so it is its own pass ahead of the GPU one.
//
// Cascades: the view from znear to `max_distance` split by the practical scheme (Zhang et al.
// 2006: `lambda` between the logarithmic and the uniform split). Each cascade is an orthographic
// projection along the sun around its slice's bounding sphere, whose radius depends on the
// camera's lens alone, so the map's footprint does not change as the camera turns; its centre is
// snapped to whole texels in world (not camera-relative) light space, so a moving camera does
// not make the shadow's edges crawl. Light depth spans the whole scene's along the sun (its
// static box and the moving instances), the same for every cascade, whatever is culled, so
// culling changes no depth the map stores.
//
// Casters are the opaque instances, static and moving, at the level of detail the main view
// draws. A caster is kept for a cascade when its box meets the slice extruded toward the sun
// (the slice's faces that face away from the sun, and planes through its silhouette edges along
// the sun's direction), every plane pushed out by `margin_texels`: a box outside that shadows
// no receiver of the slice, nor any texel the resolve's filter reads around one, as long as the
// margin covers the filter ((filter_radius + 1)·√2 texels; and, along the sun, receiver_slope
// times that for the resolve's receiver-plane bias). A caster inside it is still dropped
// when its box swept along the sun to the cascade's far light depth or the scene's lowest point
// (where its shadow can fall), grown by the margins, is hidden behind cull.main's occluders (cull.occlusion): whatever
// it shadows is then no visible pixel. So culling on and off give the same shadow.sun (tested).
// A caster that passes both is still dropped when, seen from the sun, it lies wholly behind
// shadow.distant_occluders (level 0 of the distant shadow, with only the occluders every cascade
// draws too: LightOccluders says how) [004 §2.2.3]. Last, with a time-of-day table (scene.tod,
// `render --tod`), a caster hidden from the light at
// the baked hours around this one is dropped (passes/scene/time_of_day.cpp says why that changes
// no texel of the map at a baked hour).
//
// Caching across frames (`cache`, [004 §2]): each cascade's draws list the static casters of
// its redrawn tiles, then its moving casters. shadow.cascades_static keeps the static casters'
// depth as history and shadow.cascades draws the moving ones over it each frame. For a layer to
// carry over as the camera moves, it must depend on nothing but where it lies: every cascade
// spans the same light depth (the scene's, LightRange), its side depends on the lens alone and
// its centre moves by whole texels, so the previous frame's texels are this frame's, shifted
// (shadow.cascades_static copies them). The static layer is cut into `tiles`² tiles, and a tile
// holds the depth of every static caster across the sun from it, at the level the view draws
// (not only those in the slice's volume, which moves with the view; a caster outside it changes
// no visibility in the slice: it shadows no receiver there, or lies beyond them from the sun).
// This pass reads its own previous record (history: empty on frame 0 and after a cut). The
// texels a move uncovers (a strip of columns and one of rows, a few texels wide) are drawn each
// frame under their own scissors: a tile that missed nothing else is then complete. A tile is
// stale when some texel of it came from a tile that was not complete, or when a static caster
// over it changed its level of detail, or its drawn-or-not, since a frame earlier; it is drawn
// again whole. Units (a cascade's strips, a tile) are redrawn as many as fit in
// `budget_triangles`, those the view needs first (the tiles the slice covers, grown by the
// resolve's margin; strips before tiles), tiles that waited longest first, else finest cascade
// first; the rest wait (`pending`, `unit_waiting`), and shadow.sun_resolve
// reads no texel of a tile that is not complete: a pixel there falls back to the next cascade
// that holds its filter, or the distant levels. A reset (no history, the layers' frame changed:
// the sun, the light depth's range, the lens, a parameter, the hour) draws every static layer
// whole, whatever the budget. A still camera draws no static caster after frame 0. With `cache`
// 0 every static layer is drawn whole each frame, culled by the volume and the view's occluders
// as the moving casters are. Why a frame reset is ShadowCullStats::reset.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>

#include "passes/core/context.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/occlusion_buffer.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"

namespace nightcap {
namespace {

using glm::dvec2;
using glm::dvec3;

constexpr uint32_t kMaxPlanes = 8;

struct Plane {
  dvec3 normal;   // inward
  double offset;  // inside where dot(normal, p) + offset ≥ 0
  double distance(const dvec3& p) const { return glm::dot(normal, p) + offset; }
};

struct Volume {
  std::vector<Plane> planes;
  // Outside when the box lies wholly outside one plane.
  bool excludes(const dvec3& lo, const dvec3& hi) const {
    for (const Plane& p : planes) {
      const dvec3 far_corner(p.normal.x >= 0 ? hi.x : lo.x, p.normal.y >= 0 ? hi.y : lo.y,
                             p.normal.z >= 0 ? hi.z : lo.z);
      if (p.distance(far_corner) < 0.0) return true;
    }
    return false;
  }
};

// Corner k of a slice: bit 0 right, bit 1 top, bit 2 far.
using Corners = std::array<dvec3, 8>;

// The slice extruded toward the sun (`to_sun`, unit), every plane moved out by `margin` metres
// and, along the sun's rays, by `depth_margin` more: the resolve carries a receiver's depth along
// its plane to texels up to `margin` away, so a caster that much deeper than it can still count.
Volume extruded_slice(const Corners& c, const dvec3& to_sun, double margin, double depth_margin) {
  // Faces as corner loops, and the slice's centre to orient each plane inward.
  static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  dvec3 centre(0.0);
  for (const dvec3& p : c) centre += p / 8.0;
  auto inward = [&](dvec3 normal, const dvec3& through) {
    normal = glm::normalize(normal);
    if (glm::dot(normal, centre - through) < 0) normal = -normal;
    return Plane{normal, -glm::dot(normal, through)};
  };
  std::array<Plane, 6> faces;
  std::array<bool, 6> kept{};
  std::vector<std::pair<double, Plane>> face_planes;  // (face area, plane): the smallest dropped first past 8
  for (int f = 0; f < 6; ++f) {
    const dvec3 &a = c[kFaces[f][0]], &b = c[kFaces[f][1]], &d = c[kFaces[f][3]], &e = c[kFaces[f][2]];
    const dvec3 cross = glm::cross(e - a, d - b);
    faces[f] = inward(cross, a);
    // Extruding toward the sun never leaves a face's half-space when its inward normal has no
    // component against the sun's direction.
    kept[f] = glm::dot(faces[f].normal, to_sun) >= -1e-12;
    if (kept[f]) face_planes.push_back({glm::length(cross), faces[f]});
  }
  Volume v;
  // Silhouette edges: shared by a kept face and a dropped one.
  for (int f = 0; f < 6; ++f) {
    if (!kept[f]) continue;
    for (int g = 0; g < 6; ++g) {
      if (kept[g]) continue;
      int shared[2], n = 0;
      for (int i : kFaces[f])
        for (int j : kFaces[g])
          if (i == j && n < 2) shared[n++] = i;
      if (n != 2) continue;
      const dvec3 normal = glm::cross(c[shared[1]] - c[shared[0]], to_sun);
      if (glm::dot(normal, normal) < 1e-24) continue;
      v.planes.push_back(inward(normal, c[shared[0]]));
    }
  }
  // Dropping a plane only enlarges the volume: past 8, the smallest faces go first.
  std::sort(face_planes.begin(), face_planes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [area, plane] : face_planes)
    if (v.planes.size() < kMaxPlanes) v.planes.push_back(plane);
  for (Plane& p : v.planes) p.offset += margin + depth_margin * std::max(0.0, glm::dot(p.normal, to_sun));
  return v;
}

// shadow.distant_occluders as an occlusion buffer from the sun [004 §2.2.3]: level 0 of the
// distant shadow, holding only what every cascade surely draws too (shadow.distant_plan's
// occluders). A caster whose box, seen from the sun, lies wholly behind its depth over the box's
// footprint grown by a texel each side, by more than `slope` times two texels of depth, draws no
// texel of a cascade: the occluder's depth is less wherever the caster's could land. Sampled at
// texel centres, so an opening narrower than a texel (25 cm at the default 256 m level) between
// occluders is not seen; the slope margin covers a surface's depth changing between centres.
// Empty (hides nothing) when the distant levels did not run.
class LightOccluders {
 public:
  LightOccluders(std::span<const uint8_t> data, std::span<const uint8_t> depth, double slope) {
    if (data.size() != sizeof(GpuDistantLevels)) return;
    const GpuDistantLevels levels = host_records<GpuDistantLevels>(data).at(0);
    resolution_ = uint32_t(levels.light_direction.w);
    if (resolution_ == 0 || depth.size() != size_t(resolution_) * resolution_ * sizeof(float)) {
      resolution_ = 0;
      return;
    }
    light_from_world_ = glm::dmat4(levels.light_from_world[0]);
    margin_ = slope * 2.0 * levels.texel_metres[0] / levels.depth_metres[0] + 1e-6;
    // A pyramid of maxima: mip m's texel holds the largest depth of its 2^m × 2^m texels.
    std::vector<float> level(size_t(resolution_) * resolution_);
    std::memcpy(level.data(), depth.data(), depth.size());
    mips_.push_back(std::move(level));
    for (uint32_t side = resolution_; side > 1; side = (side + 1) / 2) {
      const std::vector<float>& fine = mips_.back();
      const uint32_t half = (side + 1) / 2;
      std::vector<float> coarse(size_t(half) * half);
      for (uint32_t y = 0; y < half; ++y)
        for (uint32_t x = 0; x < half; ++x) {
          float m = 0.0f;
          for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dx = 0; dx < 2; ++dx)
              m = std::max(m, fine[size_t(std::min(2 * y + dy, side - 1)) * side + std::min(2 * x + dx, side - 1)]);
          coarse[size_t(y) * half + x] = m;
        }
      mips_.push_back(std::move(coarse));
    }
  }

  // Whether the camera-relative box is wholly behind the occluders, seen from the sun.
  bool hides(const Box& box) const {
    if (resolution_ == 0) return false;
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    double nearest = INFINITY;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec4 clip =
          light_from_world_ *
          glm::dvec4(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z, 1.0);
      lo = glm::min(lo, glm::dvec2(clip));
      hi = glm::max(hi, glm::dvec2(clip));
      nearest = std::min(nearest, clip.z);
    }
    const double n = resolution_;
    const double x0 = std::floor((lo.x * 0.5 + 0.5) * n) - 1, x1 = std::floor((hi.x * 0.5 + 0.5) * n) + 1;
    const double y0 = std::floor((lo.y * 0.5 + 0.5) * n) - 1, y1 = std::floor((hi.y * 0.5 + 0.5) * n) + 1;
    if (!(x0 >= 0 && y0 >= 0 && x1 < n && y1 < n)) return false;
    // The mip at which the footprint spans at most 2 × 2 texels, then at most 3 × 3 of them.
    uint32_t mip = 0;
    while (mip + 1 < mips_.size() && (uint32_t(x1 - x0) >> mip) > 1) ++mip;
    while (mip + 1 < mips_.size() && (uint32_t(y1 - y0) >> mip) > 1) ++mip;
    const uint32_t side = (resolution_ + (1u << mip) - 1) >> mip;
    float deepest = 0.0f;
    for (uint32_t y = uint32_t(y0) >> mip; y <= (uint32_t(y1) >> mip); ++y)
      for (uint32_t x = uint32_t(x0) >> mip; x <= (uint32_t(x1) >> mip); ++x)
        deepest = std::max(deepest, mips_[mip][size_t(y) * side + x]);
    return double(deepest) < nearest - margin_;
  }

 private:
  uint32_t resolution_ = 0;
  glm::dmat4 light_from_world_{1.0};
  double margin_ = 0.0;
  std::vector<std::vector<float>> mips_;
};

class ShadowCuller {
 public:
  explicit ShadowCuller(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        constants_(host_records<GpuFrameConstants>(ctx.host("frame.constants")).at(0)),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())),
        occlusion_(OcclusionBuffer::from_record(ctx.host("cull.occlusion"))),
        light_occluders_(ctx.flag("light_occlusion") ? ctx.host("shadow.distant_data") : std::span<const uint8_t>(),
                         ctx.host("shadow.distant_occluders"), ctx.param_float("receiver_slope")),
        culling_(ctx.flag("culling")) {
    std::memcpy(&world_[0][0], camera_.world, sizeof(camera_.world));
    eye_ = dvec3(world_[3]);
    if (!(camera_.width > 0 && camera_.height > 0)) throw GraphError("shadow.cull: frame.camera has no size");
    view_projection_ = reversed_z_projection(camera_.yfov, double(camera_.width) / camera_.height, camera_.znear) *
                       relative_view(world_);
    travel_ = glm::normalize(dvec3(glm::vec3(constants_.sun_direction)));
    const std::span<const uint8_t> tod = ctx.host("scene.tod");
    if (!tod.empty()) {
      TodRecordHeader header{};
      if (tod.size() >= sizeof(header)) std::memcpy(&header, tod.data(), sizeof(header));
      if (tod.size() < sizeof(header) || header.instances != instances_.size() ||
          tod.size() != sizeof(header) + size_t(header.instances) * sizeof(uint32_t))
        throw GraphError("shadow.cull: scene.tod does not hold a mask for each of the " +
                         std::to_string(instances_.size()) + " instances");
      if (!(header.hour >= 0.0f && header.hour < 24.0f))
        throw GraphError("shadow.cull: scene.tod's hour " + std::to_string(header.hour) + " is outside [0, 24)");
      tod_visible_ = host_view<uint32_t>(tod.subspan(sizeof(header)));
      tod_bits_ = tod_hour_bits(header.hour);
    }
  }

  void run() {
    // No sun above the horizon: the graph skips the pass (the scene has no sun_above_horizon) and
    // leaves its outputs empty, and a replay of that skip runs it on the recorded inputs, so it
    // writes nothing either.
    if (!(constants_.sun_direction.w > 0.0f && travel_.y < 0.0)) {
      for (const char* name : {"shadow.cascade_data", "draws.shadow.cascades", "shadow.cull_stats"})
        ctx_.store<uint8_t>(name, {});
      return;
    }
    const uint32_t resolution = uint32_t(ctx_.param_int("resolution"));
    const uint32_t tiles = uint32_t(ctx_.param_int("tiles"));
    if (resolution % 2 != 0) throw GraphError("shadow.cull: resolution must be even");
    if (resolution % tiles != 0)
      throw GraphError("shadow.cull: tiles (" + std::to_string(tiles) + ") must divide the resolution (" +
                       std::to_string(resolution) + ")");
    axes_ = LightAxes::of_sun(travel_);
    const LightRange range = light_range();
    const bool cache = ctx_.flag("cache");
    const std::array<double, kShadowCascades + 1> splits = split_distances();
    std::array<Cascade, kShadowCascades> cascades;
    for (uint32_t k = 0; k < kShadowCascades; ++k)
      cascades[k] = cascade(splits[k], splits[k + 1], resolution, tiles, range);

    stats_.tiles_per_side = tiles;
    stats_.resolution = resolution;
    stats_.budget_triangles = uint32_t(ctx_.param_int("budget_triangles"));
    const float key[12] = {float(travel_.x),
                           float(travel_.y),
                           float(travel_.z),
                           float(range.near),
                           float(range.depth),
                           float(cascades[0].map.texel),
                           float(cascades[1].map.texel),
                           float(cascades[2].map.texel),
                           float(cascades[3].map.texel),
                           float(resolution),
                           float(tiles),
                           float(tod_bits_)};
    std::copy(std::begin(key), std::end(key), stats_.frame_key);
    const ShadowCullStats* before = previous_record();
    CascadeReset reset = CascadeReset::none;
    if (!cache)
      reset = CascadeReset::cache_off;
    else if (!before)
      reset = CascadeReset::no_history;
    else if (std::memcmp(before->frame_key, stats_.frame_key, sizeof(key)) != 0)
      reset = CascadeReset::frame_changed;
    stats_.reset = uint32_t(reset);

    // The static layers' tiles: stale where the previous frame's layer holds nothing for them
    // (moved off it, not complete there) or where a static caster changed its level of detail.
    const std::vector<LightRect> changed =
        reset == CascadeReset::none ? level_changes(cascades) : std::vector<LightRect>{};
    std::array<uint64_t, kShadowCascades> stale{}, partial{}, needed{}, refreshed{};
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      Cascade& c = cascades[k];
      stats_.centre[2 * k] = c.centre.x;
      stats_.centre[2 * k + 1] = c.centre.y;
      const uint64_t all = c.map.all();
      if (reset != CascadeReset::none) {
        stale[k] = all;
      } else {
        c.shift = c.centre - glm::ivec2(before->centre[2 * k], before->centre[2 * k + 1]);
        stats_.shift[2 * k] = c.shift.x;
        stats_.shift[2 * k + 1] = c.shift.y;
        const uint64_t complete_before = ShadowCullStats::mask(before->complete, k);
        const TilesAfterMove moved = tiles_after_move(complete_before, c.shift, tiles, resolution);
        uint64_t whole = moved.stale;
        for (const LightRect& r : changed) whole |= c.map.meeting(r);
        // A tile that missed only what the move uncovered is complete once the strips are drawn.
        partial[k] = moved.uncovered & ~whole;
        stale[k] = whole | moved.uncovered;
        // How long each stale tile has waited: one more frame than the tile its centre came from,
        // when that one was waiting too.
        const int32_t side = int32_t(resolution / tiles);
        for (uint32_t t = 0; t < tiles * tiles; ++t) {
          if (!(stale[k] >> t & 1u)) continue;
          const MapTexels r = c.map.tile_texels(t);
          const glm::ivec2 from = glm::ivec2(r.x0, r.y0) + side / 2 + c.shift;
          if (glm::any(glm::lessThan(from, glm::ivec2(0))) ||
              glm::any(glm::greaterThanEqual(from, glm::ivec2(int32_t(resolution)))))
            continue;
          const uint32_t source = uint32_t(from.y / side) * tiles + uint32_t(from.x / side);
          if (!(complete_before >> source & 1u))
            stats_.unit_waiting[k * tiles * tiles + t] = before->unit_waiting[k * tiles * tiles + source] + 1;
        }
      }
      needed[k] = reset == CascadeReset::cache_off ? all : c.map.meeting(c.footprint);
    }

    // A reset draws each static layer whole: with the cache off, the casters its volume and the
    // view keep; else every one across the sun from its map.
    std::array<std::vector<GpuDraw>, kShadowCascades> statics;
    if (reset == CascadeReset::none) {
      const Refresh done = refresh(cascades, stale, partial, needed);
      refreshed = done.tiles;
      stats_.strips = done.strips;
    } else if (reset == CascadeReset::cache_off) {
      for (uint32_t k = 0; k < kShadowCascades; ++k) casters(cascades[k], k, true, statics[k]);
    } else {
      whole_layers(cascades, statics);
    }
    if (reset != CascadeReset::none)
      for (uint32_t k = 0; k < kShadowCascades; ++k) {
        refreshed[k] = cascades[k].map.all();
        sort_for_batching(statics[k]);
        for (const GpuDraw& d : statics[k]) stats_.static_triangles += d.index_count / 3;
      }

    GpuShadowCascades data{};
    data.light_direction = glm::vec4(glm::vec3(travel_), float(resolution));
    std::vector<GpuDraw> all;
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      const Cascade& c = cascades[k];
      data.light_from_world[k] = c.light_from_world;
      data.splits[k] = float(splits[k + 1]);
      data.texel_metres[k] = float(c.map.texel);
      data.depth_metres[k] = float(range.depth);
      stats_.planes[k] = uint32_t(c.volume.planes.size());
      stats_.first_draw[k] = uint32_t(all.size());
      std::vector<GpuDraw> moving;
      casters(c, k, false, moving);
      sort_for_batching(moving);
      if (reset != CascadeReset::none) {
        all.insert(all.end(), statics[k].begin(), statics[k].end());
      } else {
        if (stats_.strips >> k & 1u) {
          stats_.strip_first_draw[k] = uint32_t(all.size());
          for (const std::vector<GpuDraw>& strip : strips_[k]) all.insert(all.end(), strip.begin(), strip.end());
        }
        for (uint32_t t = 0; t < tiles * tiles; ++t) {
          if (!(refreshed[k] >> t & 1u)) continue;
          const uint32_t unit = k * tiles * tiles + t;
          stats_.unit_first_draw[unit] = uint32_t(all.size());
          all.insert(all.end(), units_[unit].begin(), units_[unit].end());
        }
      }
      all.insert(all.end(), moving.begin(), moving.end());
      for (uint32_t d = stats_.first_draw[k]; d < all.size(); ++d) stats_.triangles[k] += all[d].index_count / 3;
      stats_.draws[k] = uint32_t(all.size()) - stats_.first_draw[k];
      stats_.moving_draws[k] = uint32_t(moving.size());
      const uint64_t complete =
          (c.map.all() & ~stale[k]) | refreshed[k] | (stats_.strips >> k & 1u ? partial[k] : uint64_t(0));
      ShadowCullStats::set_mask(stats_.stale, k, stale[k]);
      ShadowCullStats::set_mask(stats_.needed, k, needed[k]);
      ShadowCullStats::set_mask(stats_.refreshed, k, refreshed[k]);
      ShadowCullStats::set_mask(stats_.complete, k, complete);
      ShadowCullStats::set_mask(stats_.partial, k, partial[k]);
      data.tiles[k] = glm::uvec4(uint32_t(complete), uint32_t(complete >> 32), tiles, 0u);
    }
    ctx_.store<GpuShadowCascades>("shadow.cascade_data", {&data, 1});
    ctx_.store<ShadowCullStats>("shadow.cull_stats", {&stats_, 1});
    ctx_.store<GpuDraw>("draws.shadow.cascades", all);
  }

 private:
  // The light depth every cascade spans: from the scene's side nearest the sun to its far side,
  // rounded outward to 16 m so that moving instances inside the static scene's box never move it.
  struct LightRange {
    double near, depth;
  };

  struct Cascade {
    glm::mat4 light_from_world;
    TiledMap map;
    glm::ivec2 centre;    // in whole texels of world light space
    glm::ivec2 shift{0};  // the previous frame's texel under this frame's (0, 0)
    LightRect footprint;  // the slice across the sun, grown by the margin: what the view needs of the map
    double far_light, margin, depth_margin;
    Volume volume;
  };

  // The cascade over view depths [a, b].
  Cascade cascade(double a, double b, uint32_t resolution, uint32_t tiles, const LightRange& range) const {
    const Corners corners = slice_corners(world_, a, b);
    dvec3 centre(0.0);
    for (const dvec3& p : corners) centre += p / 8.0;
    double radius = 0.0;
    for (const dvec3& p : corners) radius = std::max(radius, glm::length(p - centre));
    radius = std::ceil(radius * 16.0) / 16.0;  // the same for every view through this lens
    Cascade c;
    const double texel = 2.0 * radius / resolution;
    // Snapped in world light space: the map's texel grid stays put as the camera moves.
    const dvec3 centre_world = centre + eye_;
    c.centre = glm::ivec2(glm::floor(axes_.across(centre_world) / texel));
    const dvec2 snapped = dvec2(c.centre) * texel;
    c.map = TiledMap{snapped - radius, texel, resolution, tiles};
    c.far_light = glm::dot(centre_world, travel_) + radius + 1.0;
    // camera-relative p → ((p + eye)·x − u) / r, ((p + eye)·y − v) / r, ((p + eye)·t − near) / depth.
    glm::dmat4 m(0.0);
    for (int i = 0; i < 3; ++i) {
      m[i][0] = axes_.x[i] / radius;
      m[i][1] = axes_.y[i] / radius;
      m[i][2] = travel_[i] / range.depth;
    }
    const dvec2 eye_across = axes_.across(eye_);
    m[3] = glm::dvec4((eye_across.x - snapped.x) / radius, (eye_across.y - snapped.y) / radius,
                      (glm::dot(eye_, travel_) - range.near) / range.depth, 1.0);
    c.light_from_world = glm::mat4(m);
    c.margin = ctx_.param_float("margin_texels") * texel;
    c.depth_margin = ctx_.param_float("receiver_slope") * c.margin;
    c.volume = extruded_slice(corners, -travel_, c.margin, c.depth_margin);
    for (const dvec3& p : corners) c.footprint.grow(axes_.across(p + eye_));
    c.footprint.lo -= c.margin + texel;
    c.footprint.hi += c.margin + texel;
    return c;
  }

  // The previous frame's record, or null when there is none to keep (frame 0, a cut, a frame
  // without cascades).
  const ShadowCullStats* previous_record() {
    const std::span<const uint8_t> bytes = ctx_.host(previous("shadow.cull_stats"));
    if (bytes.size() != sizeof(ShadowCullStats)) return nullptr;
    std::memcpy(&previous_, bytes.data(), sizeof(ShadowCullStats));
    return &previous_;
  }

  // Across the sun, the boxes of the static casters within the cascades' maps that a frame ago
  // were drawn at another level of detail or not at all (both levels' boxes): their tiles hold
  // the other level's depth. Also counts them (level_changes).
  std::vector<LightRect> level_changes(const std::array<Cascade, kShadowCascades>& cascades) {
    glm::dmat4 previous_world;
    std::memcpy(&previous_world[0][0], camera_.previous_world, sizeof(camera_.previous_world));
    const dvec3 previous_eye(previous_world[3]);
    std::vector<LightRect> maps;
    for (const Cascade& c : cascades) maps.push_back(c.map.whole());
    std::vector<LightRect> changed;
    visit_static_across_sun(hierarchy_, axes_, maps, [&](uint32_t index) {
      const glm::dmat4 model = model_of(index, eye_, camera_.time);
      const MeshRecord* now = drawn_mesh(index, model);
      const MeshRecord* then = drawn_mesh(index, model_of(index, previous_eye, camera_.time - camera_.time_step));
      if (now == then) return;
      ++stats_.level_changes;
      LightRect r;
      for (const MeshRecord* mesh : {now, then}) {
        if (!mesh) continue;
        const Box box = box_of(model, *mesh);
        const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
        r.grow(across.lo);
        r.grow(across.hi);
      }
      changed.push_back(r);
    });
    return changed;
  }

  // Whether a static caster across the sun from one of cascade k's areas is drawn there: not
  // when it lies behind the sun's occluders or the time of day hides it (neither changes a
  // texel, see above). `first`: the first of the cascade's areas it meets, to count it once.
  bool keeps_static(uint32_t index, const Box& box, const MeshRecord& mesh, uint32_t k, bool first) {
    const uint32_t triangles = mesh.index_count / 3;
    if (first) ++stats_.casters_tested[k];
    if (light_occluders_.hides(box)) {
      if (first) ++stats_.casters_light_hidden[k];
      stats_.light_hidden_triangles[k] += triangles;
      if (culling_) return false;
    }
    if (!tod_visible_.empty() && !(tod_visible_[index] & tod_bits_)) {
      if (first) ++stats_.casters_tod_dropped[k];
      stats_.tod_triangles_saved[k] += triangles;
      return false;
    }
    return true;
  }

  // Each static layer after a reset: every static caster across the sun from its map.
  void whole_layers(const std::array<Cascade, kShadowCascades>& cascades,
                    std::array<std::vector<GpuDraw>, kShadowCascades>& statics) {
    std::vector<LightRect> maps;
    for (const Cascade& c : cascades) maps.push_back(c.map.whole());
    visit_static_across_sun(hierarchy_, axes_, maps, [&](uint32_t index) {
      Box box;
      const MeshRecord* mesh = nullptr;
      if (!world_box(index, box, &mesh, eye_, camera_.time)) return;
      const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
      for (uint32_t k = 0; k < kShadowCascades; ++k)
        if (across.meets(maps[k]) && keeps_static(index, box, *mesh, k, true))
          statics[k].push_back(draw_of(index, *mesh));
    });
  }

  // What to redraw this frame: each cascade's strips, when a tile misses only the texels they
  // hold, and its stale tiles; the strips the view needs first (they keep their tiles complete
  // for a fraction of a tile's cost), then the tiles it needs, then the others, tiles that have
  // waited longest first (else finest cascade first), while their triangles fit the budget (the
  // first even when it alone is over). Their draws are left in units_ and strips_.
  struct Refresh {
    std::array<uint64_t, kShadowCascades> tiles{};
    uint32_t strips = 0;  // bit k: cascade k's strips
  };
  Refresh refresh(const std::array<Cascade, kShadowCascades>& cascades,
                  const std::array<uint64_t, kShadowCascades>& stale,
                  const std::array<uint64_t, kShadowCascades>& partial,
                  const std::array<uint64_t, kShadowCascades>& needed) {
    const uint32_t per_cascade = cascades[0].map.tiles * cascades[0].map.tiles;
    // Rectangles to gather casters for, with the unit they are scheduled in (a tile, or both
    // strips of cascade k: kCascadeUnits + k) and their draws' list.
    struct Area {
      uint32_t unit;
      std::vector<GpuDraw>* list;
      LightRect rect;
    };
    units_.assign(kCascadeUnits, {});
    strips_ = {};
    std::vector<Area> areas;
    // The needed strips, the needed tiles, then the others; tiles longest waiting first.
    std::vector<uint32_t> order[3];
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      const TiledMap& map = cascades[k].map;
      if (partial[k]) {
        const UncoveredStrips strips = uncovered_strips(map.resolution, cascades[k].shift);
        order[(partial[k] & needed[k]) ? 0 : 2].push_back(kCascadeUnits + k);
        if (!strips.columns.empty()) areas.push_back({kCascadeUnits + k, &strips_[k][0], map.texels(strips.columns)});
        if (!strips.rows.empty()) areas.push_back({kCascadeUnits + k, &strips_[k][1], map.texels(strips.rows)});
      }
      for (uint32_t t = 0; t < per_cascade; ++t)
        if ((stale[k] & ~partial[k]) >> t & 1u) {
          order[(needed[k] >> t & 1u) ? 1 : 2].push_back(k * per_cascade + t);
          areas.push_back({k * per_cascade + t, &units_[k * per_cascade + t], map.tile(t)});
        }
    }
    for (std::vector<uint32_t>& units : order)
      std::stable_sort(units.begin(), units.end(), [&](uint32_t a, uint32_t b) {
        return (a < kCascadeUnits ? stats_.unit_waiting[a] : 0) > (b < kCascadeUnits ? stats_.unit_waiting[b] : 0);
      });
    std::vector<uint32_t> triangles_of(kCascadeUnits + kShadowCascades, 0);
    auto cascade_of = [&](uint32_t unit) { return unit >= kCascadeUnits ? unit - kCascadeUnits : unit / per_cascade; };
    std::vector<LightRect> rects;
    for (const Area& a : areas) rects.push_back(a.rect);
    visit_static_across_sun(hierarchy_, axes_, rects, [&](uint32_t index) {
      Box box;
      const MeshRecord* mesh = nullptr;
      if (!world_box(index, box, &mesh, eye_, camera_.time)) return;
      const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
      uint32_t met = 0;  // cascades whose areas it meets
      std::optional<GpuDraw> draw;
      for (const Area& a : areas) {
        if (!across.meets(a.rect)) continue;
        const uint32_t k = cascade_of(a.unit);
        const bool first = !(met >> k & 1u);
        met |= 1u << k;
        if (!keeps_static(index, box, *mesh, k, first)) continue;
        if (!draw) draw = draw_of(index, *mesh);
        a.list->push_back(*draw);
        triangles_of[a.unit] += mesh->index_count / 3;
      }
    });
    Refresh done;
    uint64_t filled = 0;
    bool any = false;
    for (const std::vector<uint32_t>& units : order)
      for (uint32_t unit : units) {
        const uint32_t k = cascade_of(unit), triangles = triangles_of[unit];
        if (unit < kCascadeUnits)
          stats_.unit_triangles[unit] = triangles;
        else
          stats_.strip_triangles[k] = triangles;
        if (any && filled + triangles > stats_.budget_triangles) {
          ++stats_.pending;
          continue;
        }
        any = true;
        filled += triangles;
        if (triangles > stats_.budget_triangles) stats_.over_budget = 1;
        if (unit >= kCascadeUnits) {
          done.strips |= 1u << k;
          for (uint32_t axis = 0; axis < 2; ++axis) {
            sort_for_batching(strips_[k][axis]);
            stats_.strip_draws[2 * k + axis] = uint32_t(strips_[k][axis].size());
          }
        } else {
          done.tiles[k] |= uint64_t(1) << (unit % per_cascade);
          sort_for_batching(units_[unit]);
          stats_.unit_draws[unit] = uint32_t(units_[unit].size());
        }
      }
    stats_.static_triangles = uint32_t(filled);
    return done;
  }

  std::array<double, kShadowCascades + 1> split_distances() const {
    const double n = camera_.znear, f = std::max(ctx_.param_float("max_distance"), 2.0 * n);
    const double lambda = ctx_.param_float("lambda");
    std::array<double, kShadowCascades + 1> s{};
    s[0] = n;
    for (uint32_t i = 1; i <= kShadowCascades; ++i) {
      const double t = double(i) / kShadowCascades;
      s[i] = lambda * n * std::pow(f / n, t) + (1.0 - lambda) * (n + (f - n) * t);
    }
    return s;
  }

  // Corners, relative to the camera at `world`, of its view between depths `a` and `b` along the view axis.
  Corners slice_corners(const glm::dmat4& world, double a, double b) const {
    const dvec3 right = glm::normalize(dvec3(world[0])), up = glm::normalize(dvec3(world[1]));
    const dvec3 forward = -glm::normalize(dvec3(world[2]));
    const double tan_y = std::tan(0.5 * camera_.yfov), tan_x = tan_y * double(camera_.width) / camera_.height;
    Corners c;
    for (int k = 0; k < 8; ++k) {
      const double d = k & 4 ? b : a;
      c[k] = forward * d + right * ((k & 1 ? 1 : -1) * tan_x * d) + up * ((k & 2 ? 1 : -1) * tan_y * d);
    }
    return c;
  }

  // The light depth the cascades span (world, along the sun's travel): the hierarchy's root box
  // and every moving instance where it is now, a metre to spare, rounded outward to 16 m. Also
  // sets bottom_, the scene's lowest point relative to the camera.
  LightRange light_range() {
    double nearest = INFINITY, farthest = -INFINITY;
    auto take = [&](const dvec3& lo, const dvec3& hi) {
      bottom_ = std::min(bottom_, lo.y - eye_.y);
      for (int k = 0; k < 8; ++k) {
        const double d = glm::dot(dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), travel_);
        nearest = std::min(nearest, d);
        farthest = std::max(farthest, d);
      }
    };
    if (!hierarchy_.static_order.empty()) {
      const HierarchyNode& root = hierarchy_.nodes[0];
      take(dvec3(root.bounds_min[0], root.bounds_min[1], root.bounds_min[2]),
           dvec3(root.bounds_max[0], root.bounds_max[1], root.bounds_max[2]));
    }
    for (uint32_t i : hierarchy_.moving) {
      Box box;
      if (world_box(i, box, nullptr, eye_, camera_.time)) take(box.min + eye_, box.max + eye_);
    }
    // Nothing to cast or receive: any range (around the eye).
    if (!std::isfinite(nearest)) nearest = farthest = glm::dot(eye_, travel_);
    constexpr double kStep = 16.0;
    const double near = std::floor((nearest - 1.0) / kStep) * kStep;
    return {near, std::ceil((farthest + 1.0) / kStep) * kStep - near};
  }

  // The instance's model matrix relative to a camera at `eye`, at `time`.
  glm::dmat4 model_of(uint32_t index, const dvec3& eye, double time) const {
    glm::dmat4 model = instance_model(instances_[index], time);
    model[3] -= glm::dvec4(eye, 0.0);
    return model;
  }

  const MeshRecord* mesh_at(uint32_t index) const {
    if (index >= meshes_.size()) throw GraphError("shadow.cull: an instance names mesh " + std::to_string(index));
    return &meshes_[index];
  }

  // The level the main view draws (cull.main picks it by the same distance), or null when the
  // instance is not drawn at all: degenerate, beyond its draw distance, or not an opaque caster.
  const MeshRecord* drawn_mesh(uint32_t index, const glm::dmat4& model) const {
    const InstanceRecord& r = instances_[index];
    if (r.material >= materials_.size()) return nullptr;
    const GpuMaterial& m = materials_[r.material];
    if (m.extra.z != float(AlphaMode::opaque) || (int(m.extra.w) & 4) != 0) return nullptr;
    const double determinant = glm::determinant(glm::dmat3(model));
    const MeshRecord* mesh = mesh_at(r.primitive);
    if (!std::isfinite(determinant) || determinant == 0.0 || mesh->index_count == 0) return nullptr;
    const dvec3 centre(model * glm::dvec4(0.5 * (mesh->bounds_min[0] + mesh->bounds_max[0]),
                                          0.5 * (mesh->bounds_min[1] + mesh->bounds_max[1]),
                                          0.5 * (mesh->bounds_min[2] + mesh->bounds_max[2]), 1.0));
    const double distance = glm::length(centre);
    uint32_t steps = 0;
    while (mesh->coarser >= 0 && distance > mesh->lod_distance) {
      if (++steps > meshes_.size()) throw GraphError("shadow.cull: mesh levels of detail form a cycle");
      mesh = mesh_at(uint32_t(mesh->coarser));
    }
    return distance > mesh->draw_distance ? nullptr : mesh;
  }

  // The box, relative to a camera at `eye`, of the instance's drawn level at `time`; false when
  // it is not drawn.
  bool world_box(uint32_t index, Box& box, const MeshRecord** drawn, const dvec3& eye, double time) const {
    const glm::dmat4 model = model_of(index, eye, time);
    const MeshRecord* mesh = drawn_mesh(index, model);
    if (!mesh) return false;
    box = box_of(model, *mesh);
    if (drawn) *drawn = mesh;
    return true;
  }

  // The box of `mesh` under `model`.
  static Box box_of(const glm::dmat4& model, const MeshRecord& mesh) {
    Box box{dvec3(INFINITY), dvec3(-INFINITY)};
    for (int k = 0; k < 8; ++k) {
      const dvec3 p(model * glm::dvec4(k & 1 ? mesh.bounds_max[0] : mesh.bounds_min[0],
                                       k & 2 ? mesh.bounds_max[1] : mesh.bounds_min[1],
                                       k & 4 ? mesh.bounds_max[2] : mesh.bounds_min[2], 1.0));
      box.min = glm::min(box.min, p);
      box.max = glm::max(box.max, p);
    }
    return box;
  }

  // Whether the camera-relative box's shadow, out to light depth `far` (camera-relative),
  // `margin` metres around and `depth_margin` toward the sun (extruded_slice says why), lies
  // wholly behind the view's occluders.
  bool shadow_hidden(const Box& box, double far, double margin, double depth_margin) const {
    double nearest = INFINITY;
    for (int k = 0; k < 8; ++k)
      nearest = std::min(nearest, glm::dot(dvec3(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                                                 k & 4 ? box.max.z : box.min.z),
                                           travel_));
    // No receiver lies past the cascade's far light depth, nor below the scene's lowest point.
    const double to_bottom = (box.max.y - bottom_) / -travel_.y;
    const dvec3 sweep = travel_ * std::max(0.0, std::min(far - nearest, to_bottom));
    const dvec3 back = -travel_ * depth_margin;
    const dvec3 lo = glm::min(glm::min(box.min, box.min + sweep), box.min + back) - margin;
    const dvec3 hi = glm::max(glm::max(box.max, box.max + sweep), box.max + back) + margin;
    glm::dvec4 corners[8];
    for (int k = 0; k < 8; ++k)
      corners[k] = view_projection_ * glm::dvec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1.0);
    return occlusion_.hidden(corners);
  }

  // The cascade's static casters (through the hierarchy: a node outside the volume drops what it
  // holds) or its moving ones, culled by its volume, the view's occluders and the sun's.
  void casters(const Cascade& c, uint32_t cascade, bool statics, std::vector<GpuDraw>& out) {
    const double far = c.far_light - glm::dot(eye_, travel_);
    auto consider = [&](uint32_t i) {
      Box box;
      const MeshRecord* mesh = nullptr;
      if (!world_box(i, box, &mesh, eye_, camera_.time)) return;
      ++stats_.casters_tested[cascade];
      if (c.volume.excludes(box.min, box.max)) {
        ++stats_.casters_culled[cascade];
        if (culling_) return;
      } else if (shadow_hidden(box, far, c.margin, c.depth_margin)) {
        ++stats_.casters_hidden[cascade];
        if (culling_) return;
      } else if (light_occluders_.hides(box)) {
        ++stats_.casters_light_hidden[cascade];
        stats_.light_hidden_triangles[cascade] += mesh->index_count / 3;
        if (culling_) return;
      }
      if (!tod_visible_.empty() && !(tod_visible_[i] & tod_bits_)) {
        ++stats_.casters_tod_dropped[cascade];
        stats_.tod_triangles_saved[cascade] += mesh->index_count / 3;
        return;
      }
      out.push_back(draw_of(i, *mesh));
    };
    if (!statics) {
      for (uint32_t i : hierarchy_.moving) consider(i);
      return;
    }
    std::vector<uint32_t> stack;
    if (!hierarchy_.static_order.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const HierarchyNode& node = hierarchy_.nodes[stack.back()];
      stack.pop_back();
      const dvec3 lo = dvec3(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]) - eye_;
      const dvec3 hi = dvec3(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]) - eye_;
      if (culling_ && c.volume.excludes(lo, hi)) {
        const uint32_t count = leaf_count(node);
        stats_.casters_tested[cascade] += count;
        stats_.casters_culled[cascade] += count;
        continue;
      }
      if (culling_ && shadow_hidden({lo, hi}, far, c.margin, c.depth_margin)) {
        const uint32_t count = leaf_count(node);
        stats_.casters_tested[cascade] += count;
        stats_.casters_hidden[cascade] += count;
        continue;
      }
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) consider(hierarchy_.static_order[k]);
      } else {
        stack.push_back(node.first + 1);
        stack.push_back(node.first);
      }
    }
  }

  uint32_t leaf_count(const HierarchyNode& node) const {
    if (node.count > 0) return node.count;
    return leaf_count(hierarchy_.nodes[node.first]) + leaf_count(hierarchy_.nodes[node.first + 1]);
  }

  GpuDraw draw_of(uint32_t index, const MeshRecord& mesh) const {
    return caster_draw(index, instances_[index], model_of(index, eye_, camera_.time), mesh);
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  GpuFrameConstants constants_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  Hierarchy hierarchy_;
  OcclusionBuffer occlusion_;
  LightOccluders light_occluders_;
  bool culling_;
  std::span<const uint32_t> tod_visible_;  // empty: no table, every caster casts
  uint16_t tod_bits_ = 0;                  // the baked hours that decide at this hour
  glm::dmat4 world_{1.0}, view_projection_{1.0};
  dvec3 eye_{0.0}, travel_{0.0};
  LightAxes axes_;
  double bottom_ = INFINITY;  // the scene's lowest point, camera-relative
  ShadowCullStats stats_{};
  ShadowCullStats previous_{};
  std::vector<std::vector<GpuDraw>> units_;  // this frame's draws of each tile it considered
  // And of each cascade's strips: the columns' and the rows' the move uncovered.
  std::array<std::array<std::vector<GpuDraw>, 2>, kShadowCascades> strips_;
};

}  // namespace

PassDecl shadow_cull_pass() {
  return PassDecl("shadow.cull", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("frame.constants", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read("cull.occlusion", Use::host)
      .read("scene.tod", Use::host)
      .read("shadow.distant_data", Use::host)
      .read("shadow.distant_occluders", Use::host)
      .read_previous("shadow.cull_stats", Use::host)
      .write("shadow.cascade_data", Use::host, BufferDecl{kinds::buffer})
      .write("draws.shadow.cascades", Use::host, BufferDecl{kinds::draw_list})
      .write("shadow.cull_stats", Use::host, BufferDecl{kinds::buffer})
      .layout("shadow.cascade_data", shadow_cascades_schema())
      .layout("draws.shadow.cascades", draw_schema())
      .layout("shadow.cull_stats", shadow_cull_stats_schema())
      .param(sun_shadow_resolution())
      .param_float("max_distance", 120, 1, 20000,
                   "metres along the view where the last cascade ends (no sun shadow beyond)")
      .param_float("lambda", 0.75, 0, 1, "practical split: 1 logarithmic, 0 uniform")
      .param_float("margin_texels", 6, 0, 64,
                   "texels each culling plane is pushed out: at least (shadow.sun_resolve.filter_radius + 1)·√2")
      .param_float("receiver_slope", 11.43, 0, 1000,
                   "the steepest receiver slope culling allows for: at least shadow.sun_resolve.max_slope")
      .param_int("tiles", 8, 1, kCascadeMaxTilesPerSide,
                 "tiles per side of a cascade: the unit of the static layers' refresh")
      .param_int("budget_triangles", 500000, 0, 1e9,
                 "static triangles shadow.cascades_static draws per frame at most, after a reset (a unit above it is "
                 "drawn alone)")
      .flag("cache", true,
            "1: the static layers (shadow.cascades_static) carry over from the previous frame and only the stale "
            "tiles the view needs are redrawn; 0: every static layer drawn whole each frame")
      .flag("light_occlusion", true,
            "1: drop casters wholly behind shadow.distant_occluders from the sun; 0: not (culling=0 turns every "
            "test off)")
      .flag("culling", true,
            "1: drop casters outside each cascade's volume or whose shadow is hidden (0 keeps them, for the tests)")
      .needs("sun_above_horizon")
      .run([](PassContext& ctx) { ShadowCuller(ctx).run(); });
}

}  // namespace nightcap
