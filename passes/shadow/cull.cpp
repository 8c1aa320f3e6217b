// shadow.cull (CPU): the sun's cascades for this frame and what each draws. frame.md's
// shadow.cascades culls "per cascade against an up-to-8-plane convex volume"; culling is CPU
// work, and a CPU pass is how the graph records it, so it is its own pass ahead of the GPU one.
//
// Cascades: the view from znear to `max_distance` split by the practical scheme (Zhang et al.
// 2006: `lambda` between the logarithmic and the uniform split). Each cascade is an orthographic
// projection along the sun around its slice's bounding sphere, whose radius depends on the
// camera's lens alone, so the map's footprint does not change as the camera turns; its centre is
// snapped to whole texels in world (not camera-relative) light space, so a moving camera does
// not make the shadow's edges crawl. Light depth spans from the scene's side nearest the sun to
// the slice's far side, whatever is culled, so culling changes no depth the map stores.
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
// Caching across frames (`cache`, [004 §2]): each cascade's draws list its static casters, then
// its moving ones. shadow.cascades_static keeps the static casters' depth as history and
// shadow.cascades draws the moving ones over it each frame. A cascade keeps the previous frame's
// static depth when this pass, recomputing the previous frame's cascade from frame.camera's
// previous_world (and the moving instances' place a frame earlier, for the light's near plane),
// gets the same eye, projection and culling volume, bit for bit, and the history is valid (not
// frame 0, not a cut): its static casters are then not even listed. With the cache on, static
// casters are culled by the volume alone, since a kept depth must not depend on what hides it
// from one frame's view. What each cascade did and why is ShadowCullStats::static_source.
// The pass cannot see a history reset the graph makes for a resize; a renderer keeps its size
// and the cascades' resolution over a run.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "passes/core/context.h"
#include "passes/cull/hierarchy.h"
#include "passes/cull/occlusion_buffer.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap {
namespace {

using glm::dvec3;

constexpr uint32_t kMaxPlanes = 8;

struct Plane {
  dvec3 normal;   // inward
  double offset;  // inside where dot(normal, p) + offset ≥ 0
  double distance(const dvec3& p) const { return glm::dot(normal, p) + offset; }
};

struct Volume {
  std::vector<Plane> planes;
  bool operator==(const Volume& other) const {
    if (planes.size() != other.planes.size()) return false;
    for (size_t i = 0; i < planes.size(); ++i)
      if (planes[i].normal != other.planes[i].normal || planes[i].offset != other.planes[i].offset) return false;
    return true;
  }
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
        light_occluders_(
            ctx.param("light_occlusion") != 0.0 ? ctx.host("shadow.distant_data") : std::span<const uint8_t>(),
            ctx.host("shadow.distant_occluders"), ctx.param("receiver_slope")),
        culling_(ctx.param("culling") != 0.0) {
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
        store(name, nullptr, 0);
      return;
    }
    const uint32_t resolution = uint32_t(ctx_.param("resolution"));
    if (resolution % 2 != 0) throw GraphError("shadow.cull: resolution must be even");
    // Light axes: any basis around the sun's direction, fixed for a given sun.
    const dvec3 helper = std::abs(travel_.y) < 0.99 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
    axis_x_ = glm::normalize(glm::cross(helper, travel_));
    axis_y_ = glm::cross(travel_, axis_x_);
    const double near_light = scene_light_near(eye_, camera_.time, &bottom_);
    GpuShadowCascades data{};
    data.light_direction = glm::vec4(glm::vec3(travel_), float(resolution));
    const std::array<double, kShadowCascades + 1> splits = split_distances();
    // The previous frame's cascades, recomputed from its camera and the same sun (the scene's
    // first directional light, fixed over a run): a cascade whose projection and culling volume
    // come out the same bits keeps its static depth. Any difference, however small, redraws.
    const bool cache = ctx_.param("cache") != 0.0;
    const bool history = camera_.frame_index > 0 && camera_.cut == 0;
    glm::dmat4 previous_world;
    std::memcpy(&previous_world[0][0], camera_.previous_world, sizeof(camera_.previous_world));
    const dvec3 previous_eye(previous_world[3]);
    const double previous_near =
        cache && history ? scene_light_near(previous_eye, camera_.time - camera_.time_step, nullptr) : 0.0;
    std::vector<GpuDraw> all;
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      const Cascade now = cascade(world_, eye_, near_light, splits[k], splits[k + 1], resolution);
      data.light_from_world[k] = now.light_from_world;
      data.splits[k] = float(splits[k + 1]);
      data.texel_metres[k] = float(now.texel);
      data.depth_metres[k] = float(now.depth);
      ShadowStaticSource source = ShadowStaticSource::redrawn_cache_off;
      if (cache && !history) {
        source = ShadowStaticSource::redrawn_reset;
      } else if (cache) {
        const Cascade before =
            cascade(previous_world, previous_eye, previous_near, splits[k], splits[k + 1], resolution);
        const bool same = previous_eye == eye_ && before.light_from_world == now.light_from_world &&
                          before.depth == now.depth && before.volume == now.volume;
        source = same ? ShadowStaticSource::reused : ShadowStaticSource::redrawn_changed;
      }
      stats_.static_source[k] = uint32_t(source);
      stats_.planes[k] = uint32_t(now.volume.planes.size());
      stats_.first_draw[k] = uint32_t(all.size());
      // Cached static depth must not depend on what hides it from this frame's view (the view's
      // occluders include moving ones), so with the cache on only the volume culls static casters.
      const CasterSet set{.statics = source != ShadowStaticSource::reused,
                          .static_occlusion = !cache,
                          .far = now.far_light - glm::dot(eye_, travel_),
                          .margin = now.margin,
                          .depth_margin = now.depth_margin,
                          .cascade = k};
      std::vector<GpuDraw> statics, moving;
      casters(now.volume, set, statics, moving);
      for (std::vector<GpuDraw>* list : {&statics, &moving}) {
        std::sort(list->begin(), list->end(), [](const GpuDraw& a, const GpuDraw& b) {
          if (a.material != b.material) return a.material < b.material;
          if (a.first_index != b.first_index) return a.first_index < b.first_index;
          return a.instance < b.instance;
        });
        for (const GpuDraw& d : *list) stats_.triangles[k] += d.index_count / 3;
        all.insert(all.end(), list->begin(), list->end());
      }
      stats_.draws[k] = uint32_t(statics.size() + moving.size());
      stats_.moving_draws[k] = uint32_t(moving.size());
    }
    store("shadow.cascade_data", &data, sizeof(data));
    store("shadow.cull_stats", &stats_, sizeof(stats_));
    store("draws.shadow.cascades", all.data(), all.size() * sizeof(GpuDraw));
  }

 private:
  struct Cascade {
    glm::mat4 light_from_world;
    double texel, depth, far_light, margin, depth_margin;
    Volume volume;
  };

  // The cascade over view depths [a, b] of a camera at `world` (eye: its position), with the
  // scene's nearest light depth `near_light`.
  Cascade cascade(const glm::dmat4& world, const dvec3& eye, double near_light, double a, double b,
                  uint32_t resolution) const {
    const Corners corners = slice_corners(world, a, b);
    dvec3 centre(0.0);
    for (const dvec3& p : corners) centre += p / 8.0;
    double radius = 0.0;
    for (const dvec3& p : corners) radius = std::max(radius, glm::length(p - centre));
    radius = std::ceil(radius * 16.0) / 16.0;  // the same for every view through this lens
    Cascade c;
    c.texel = 2.0 * radius / resolution;
    // Snapped in world light space: the map's texel grid stays put as the camera moves.
    const dvec3 centre_world = centre + eye;
    const double u = std::floor(glm::dot(centre_world, axis_x_) / c.texel) * c.texel;
    const double v = std::floor(glm::dot(centre_world, axis_y_) / c.texel) * c.texel;
    c.far_light = glm::dot(centre_world, travel_) + radius + 1.0;
    const double near = std::min(near_light, c.far_light - 2.0 * radius - 2.0);
    c.depth = c.far_light - near;
    // camera-relative p → ((p + eye)·x − u) / r, ((p + eye)·y − v) / r, ((p + eye)·t − near) / depth.
    glm::dmat4 m(0.0);
    for (int i = 0; i < 3; ++i) {
      m[i][0] = axis_x_[i] / radius;
      m[i][1] = axis_y_[i] / radius;
      m[i][2] = travel_[i] / c.depth;
    }
    m[3] = glm::dvec4((glm::dot(eye, axis_x_) - u) / radius, (glm::dot(eye, axis_y_) - v) / radius,
                      (glm::dot(eye, travel_) - near) / c.depth, 1.0);
    c.light_from_world = glm::mat4(m);
    c.margin = ctx_.param("margin_texels") * c.texel;
    c.depth_margin = ctx_.param("receiver_slope") * c.margin;
    c.volume = extruded_slice(corners, -travel_, c.margin, c.depth_margin);
    return c;
  }

  void store(const char* name, const void* bytes, size_t size) {
    auto& out = ctx_.output(name);
    out.resize(size);
    if (size) std::memcpy(out.data(), bytes, size);
  }

  std::array<double, kShadowCascades + 1> split_distances() const {
    const double n = camera_.znear, f = std::max(ctx_.param("max_distance"), 2.0 * n);
    const double lambda = ctx_.param("lambda");
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

  // The least light depth (along the sun's travel, world) of anything in the scene: the
  // hierarchy's root box and every moving instance where it is at `time`, the camera at `eye`
  // (which picks the level drawn). Also sets *bottom to the scene's lowest point relative to it.
  double scene_light_near(const dvec3& eye, double time, double* bottom) const {
    double nearest = INFINITY;
    auto take = [&](const dvec3& lo, const dvec3& hi) {
      if (bottom) *bottom = std::min(*bottom, lo.y - eye.y);
      for (int k = 0; k < 8; ++k)
        nearest =
            std::min(nearest, glm::dot(dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), travel_));
    };
    if (!hierarchy_.static_order.empty()) {
      const HierarchyNode& root = hierarchy_.nodes[0];
      take(dvec3(root.bounds_min[0], root.bounds_min[1], root.bounds_min[2]),
           dvec3(root.bounds_max[0], root.bounds_max[1], root.bounds_max[2]));
    }
    for (uint32_t i : hierarchy_.moving) {
      Box box;
      if (world_box(i, box, nullptr, eye, time)) take(box.min + eye, box.max + eye);
    }
    return std::isfinite(nearest) ? nearest - 1.0 : glm::dot(eye, travel_);
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
    box.min = dvec3(INFINITY);
    box.max = dvec3(-INFINITY);
    for (int k = 0; k < 8; ++k) {
      const dvec3 p(model * glm::dvec4(k & 1 ? mesh->bounds_max[0] : mesh->bounds_min[0],
                                       k & 2 ? mesh->bounds_max[1] : mesh->bounds_min[1],
                                       k & 4 ? mesh->bounds_max[2] : mesh->bounds_min[2], 1.0));
      box.min = glm::min(box.min, p);
      box.max = glm::max(box.max, p);
    }
    if (drawn) *drawn = mesh;
    return true;
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

  // Which casters of a cascade to list, and its culling margins.
  struct CasterSet {
    bool statics;           // list static casters (not when the cascade keeps its static depth)
    bool static_occlusion;  // drop static casters whose shadow the view's occluders hide
    double far, margin, depth_margin;
    uint32_t cascade;
  };

  void casters(const Volume& volume, const CasterSet& set, std::vector<GpuDraw>& statics,
               std::vector<GpuDraw>& moving) {
    const uint32_t cascade = set.cascade;
    auto consider = [&](uint32_t i, bool occlusion, std::vector<GpuDraw>& out) {
      Box box;
      const MeshRecord* mesh = nullptr;
      if (!world_box(i, box, &mesh, eye_, camera_.time)) return;
      ++stats_.casters_tested[cascade];
      if (volume.excludes(box.min, box.max)) {
        ++stats_.casters_culled[cascade];
        if (culling_) return;
      } else if (occlusion && shadow_hidden(box, set.far, set.margin, set.depth_margin)) {
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
    // Static instances through the hierarchy: a node outside the volume drops what it holds.
    std::vector<uint32_t> stack;
    if (set.statics && !hierarchy_.static_order.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const HierarchyNode& node = hierarchy_.nodes[stack.back()];
      stack.pop_back();
      const dvec3 lo = dvec3(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]) - eye_;
      const dvec3 hi = dvec3(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]) - eye_;
      if (culling_ && volume.excludes(lo, hi)) {
        const uint32_t count = leaf_count(node);
        stats_.casters_tested[cascade] += count;
        stats_.casters_culled[cascade] += count;
        continue;
      }
      if (culling_ && set.static_occlusion && shadow_hidden({lo, hi}, set.far, set.margin, set.depth_margin)) {
        const uint32_t count = leaf_count(node);
        stats_.casters_tested[cascade] += count;
        stats_.casters_hidden[cascade] += count;
        continue;
      }
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k)
          consider(hierarchy_.static_order[k], set.static_occlusion, statics);
      } else {
        stack.push_back(node.first + 1);
        stack.push_back(node.first);
      }
    }
    for (uint32_t i : hierarchy_.moving) consider(i, true, moving);
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
  dvec3 axis_x_{0.0}, axis_y_{0.0};  // the light's axes across the map
  double bottom_ = INFINITY;         // the scene's lowest point, camera-relative
  ShadowCullStats stats_{};
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
      .write("shadow.cascade_data", Use::host, BufferDecl{ResourceKind::buffer})
      .write("draws.shadow.cascades", Use::host, BufferDecl{ResourceKind::draw_list})
      .write("shadow.cull_stats", Use::host, BufferDecl{ResourceKind::buffer})
      .layout("shadow.cascade_data", shadow_cascades_schema())
      .layout("draws.shadow.cascades", draw_schema())
      .layout("shadow.cull_stats", shadow_cull_stats_schema())
      .param("resolution", kShadowResolution, 64, 4096, "texels per side of each cascade (even)")
      .param("max_distance", 120, 1, 20000, "metres along the view where the last cascade ends (no sun shadow beyond)")
      .param("lambda", 0.75, 0, 1, "practical split: 1 logarithmic, 0 uniform")
      .param("margin_texels", 6, 0, 64,
             "texels each culling plane is pushed out: at least (shadow.sun_resolve.filter_radius + 1)·√2")
      .param("receiver_slope", 11.43, 0, 1000,
             "the steepest receiver slope culling allows for: at least shadow.sun_resolve.max_slope")
      .param("cache", 1, 0, 1,
             "1: a cascade whose projection and culling volume are the previous frame's keeps its static casters' "
             "depth (shadow.cascades_static) and draws only the moving ones; 0: everything drawn each frame")
      .param("light_occlusion", 1, 0, 1,
             "1: drop casters wholly behind shadow.distant_occluders from the sun; 0: not (culling=0 turns every "
             "test off)")
      .param("culling", 1, 0, 1,
             "1: drop casters outside each cascade's volume or whose shadow is hidden (0 keeps them, for the tests)")
      .needs("sun_above_horizon")
      .run([](PassContext& ctx) { ShadowCuller(ctx).run(); });
}

}  // namespace nightcap
