// ShadowCuller's frame: the cascades fitted to the view's slices, the light depth they span, and
// the plan that run() records from them and the casters (shadow_culler_casters.cpp): each
// cascade's draws, the static layers' tiles and the statistics the next frame reads.
#include "passes/shadow/shadow_culler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string>

#include "passes/frame/camera_math.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/caster_draw.h"

namespace nightcap::shadow_cull {

using glm::dvec2;

ShadowCuller::ShadowCuller(PassContext& ctx)
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

void ShadowCuller::run() {
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

ShadowCuller::Cascade ShadowCuller::cascade(double a, double b, uint32_t resolution, uint32_t tiles,
                                            const LightRange& range) const {
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

const ShadowCullStats* ShadowCuller::previous_record() {
  const std::span<const uint8_t> bytes = ctx_.host(previous("shadow.cull_stats"));
  if (bytes.size() != sizeof(ShadowCullStats)) return nullptr;
  std::memcpy(&previous_, bytes.data(), sizeof(ShadowCullStats));
  return &previous_;
}

std::array<double, kShadowCascades + 1> ShadowCuller::split_distances() const {
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

Corners ShadowCuller::slice_corners(const glm::dmat4& world, double a, double b) const {
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

ShadowCuller::LightRange ShadowCuller::light_range() {
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

}  // namespace nightcap::shadow_cull
