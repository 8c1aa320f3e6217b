// shadow.distant_plan (CPU): where the sun's distant shadow levels lie this frame and which part
// of them shadow.distant redraws (frame.md section 1, [004 §2.1]). Collecting the casters cannot
// be spread over frames [004 §2.1]: every unit's casters are counted every frame (the schedule
// needs them all), and the draws of this frame's units are built.
//
// Levels: four orthographic maps along the sun, level k covering a square of side E·4^k, where
// E is `level0_metres`, grown when four levels at that size would not reach across the static
// scene: the last level then covers the whole map (its light-space square around the static
// scene's box, with a texel of room for snapping). The last level is centred on the map; the
// others on the camera, their centres snapped to an eighth of their side in world light space,
// so they move rarely and by whole texels: shadow.distant keeps what a moved level already
// holds by reading the previous frame's texel that covers the same place (refresh.xy; the
// previous frame's centres are in its record). Light depth spans the static scene's box, the same at every level and
// every frame.
//
// Refresh: each level is cut into `tiles`² tiles, the units of refresh. The plan reads its own
// previous record (history: empty on frame 0 and after a camera cut), which says where each
// level lay and which of its units held their casters' depth (`complete`). A level that moved
// keeps a unit complete only when every texel it now covers was covered by complete units
// before; the others are stale. Stale units are redrawn, finest level first, as many as fit in
// `budget_triangles` (a unit alone above the budget gets a frame of its own, flagged
// over_budget); the rest wait for the next frames (`pending`). With no history, or when the
// levels' frame changed (the sun, the scene's extent, a parameter), or with `cache` 0, every unit
// is redrawn whatever the budget, so the frame after a reset has complete distant shadows
// (recorded as `reset`, DistantReset). Static casters and a fixed sun never make a complete unit
// stale: a still camera redraws nothing after frame 0, a driving one only what its levels' moves
// uncover.
// Occluders: with each tile of level 0 it redraws, the draws of the static instances flagged
// kInstanceShadowOccluder, only their finest mesh's occluder triangles (which every level of
// detail they may be drawn at has, at any distance): shadow.distant draws them into
// shadow.distant_occluders, level 0's depth of what surely is in every cascade too, which
// shadow.cull reads to drop casters hidden from the sun [004 §2.2.3].
//
// Casters: the static opaque instances (moving ones would leave stale shadows behind in a map
// refreshed every few frames), at their coarsest level of detail, whatever their draw distance
// (a level is the same from wherever the camera is, so tiles drawn in different frames agree).
// A caster is kept for a tile when its box, projected across the sun, meets the tile grown by a
// texel; a texel's depth is the nearest of the casters covering it, so the kept set gives the
// tile the same depths as drawing every caster.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"

namespace nightcap {
namespace {

using glm::dvec2;
using glm::dvec3;

struct Unit {
  uint32_t triangles = 0;
  std::vector<GpuDraw> draws;
  std::vector<GpuDraw> occluders;  // level 0's tiles: the shadow occluders' occluder triangles
};

class DistantPlanner {
 public:
  explicit DistantPlanner(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        constants_(host_records<GpuFrameConstants>(ctx.host("frame.constants")).at(0)),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())) {
    axes_ = LightAxes::of_sun(glm::normalize(dvec3(glm::vec3(constants_.sun_direction))));
  }

  void run() {
    // As shadow.cull: a replay of the skip runs the pass on the recorded inputs, and it writes nothing.
    if (!(constants_.sun_direction.w > 0.0f && axes_.travel.y < 0.0)) {
      for (const char* name : {"shadow.distant_data", "draws.shadow.distant", "shadow.distant_plan"})
        ctx_.store<uint8_t>(name, {});
      return;
    }
    const uint32_t resolution = uint32_t(ctx_.param_int("resolution"));
    const uint32_t tiles = uint32_t(ctx_.param_int("tiles"));
    if (resolution % 8 != 0) throw GraphError("shadow.distant_plan: resolution must be a multiple of 8");
    if (resolution % tiles != 0) throw GraphError("shadow.distant_plan: tiles must divide the resolution");
    // The static scene in light space (a box around the eye when there is none).
    LightRect map;
    double near = INFINITY, far = -INFINITY;
    dvec3 lo = dvec3(eye()) - 1.0, hi = dvec3(eye()) + 1.0;
    if (!hierarchy_.static_order.empty()) {
      const HierarchyNode& root = hierarchy_.nodes[0];
      lo = dvec3(root.bounds_min[0], root.bounds_min[1], root.bounds_min[2]);
      hi = dvec3(root.bounds_max[0], root.bounds_max[1], root.bounds_max[2]);
    }
    for (int k = 0; k < 8; ++k) {
      const dvec3 p(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      map.grow(axes_.across(p));
      near = std::min(near, glm::dot(p, axes_.travel));
      far = std::max(far, glm::dot(p, axes_.travel));
    }
    near -= 1.0;
    const double depth = far + 1.0 - near;
    const double map_side = std::max(map.hi.x - map.lo.x, map.hi.y - map.lo.y) + 2.0;
    const double last_scale = std::pow(4.0, kDistantLevels - 1);
    // Snapping moves a centre by less than a texel: the last level keeps a texel of room each side.
    const double side0 =
        std::max(ctx_.param_float("level0_metres"), map_side / (last_scale * (1.0 - 2.0 / resolution)));

    DistantPlan plan{};
    plan.tiles_per_side = tiles;
    plan.resolution = resolution;
    plan.budget_triangles = uint32_t(ctx_.param_int("budget_triangles"));
    plan.units = kDistantLevels * tiles * tiles;
    const float key[6] = {float(axes_.travel.x), float(axes_.travel.y), float(axes_.travel.z),
                          float(side0),          float(near),           float(depth)};
    std::copy(std::begin(key), std::end(key), plan.frame_key);
    const DistantPlan* before = previous_plan();
    if (!ctx_.flag("cache"))
      plan.reset = uint32_t(DistantReset::cache_off);
    else if (!before)
      plan.reset = uint32_t(DistantReset::no_history);
    else if (before->tiles_per_side != tiles || before->resolution != resolution ||
             std::memcmp(before->frame_key, plan.frame_key, sizeof(key)) != 0)
      plan.reset = uint32_t(DistantReset::levels_changed);

    GpuDistantLevels data{};
    data.light_direction = glm::vec4(glm::vec3(axes_.travel), float(resolution));
    const dvec3 eye_now = eye();
    const dvec2 map_centre = 0.5 * (map.lo + map.hi);
    std::vector<LightRect> tile_rects;
    for (uint32_t k = 0; k < kDistantLevels; ++k) {
      const double side = side0 * std::pow(4.0, k), texel = side / resolution;
      const bool last = k + 1 == kDistantLevels;
      const dvec2 wanted = last ? map_centre : axes_.across(eye_now);
      const double step = last ? texel : side / 8.0;
      const dvec2 centre = glm::floor(wanted / step) * step;
      // Whole texels: the centre is a multiple of a texel (an eighth of a side is resolution / 8 of them).
      const glm::ivec2 centre_texels(glm::round(centre / texel));
      plan.centre[2 * k] = centre_texels.x;
      plan.centre[2 * k + 1] = centre_texels.y;
      // The texel of the previous frame's level that this frame's texel (0, 0) covers.
      const glm::ivec2 shift =
          plan.reset ? glm::ivec2(0) : centre_texels - glm::ivec2(before->centre[2 * k], before->centre[2 * k + 1]);
      data.refresh[k] = glm::ivec4(shift.x, shift.y, 0, int(tiles));
      if (plan.reset) {
        plan.stale[k] = all_tiles(tiles);
      } else {
        const TilesAfterMove moved = tiles_after_move(before->complete[k], shift, tiles, resolution);
        plan.stale[k] = uint32_t(moved.stale | moved.uncovered);
      }
      // camera-relative p → ((p + eye)·x − cx) / (side / 2), ((p + eye)·y − cy) / (side / 2), ((p + eye)·t − near) /
      // depth.
      const double half = 0.5 * side;
      glm::dmat4 m(0.0);
      for (int c = 0; c < 3; ++c) {
        m[c][0] = axes_.x[c] / half;
        m[c][1] = axes_.y[c] / half;
        m[c][2] = axes_.travel[c] / depth;
      }
      const dvec2 eye_across = axes_.across(eye_now);
      m[3] = glm::dvec4((eye_across.x - centre.x) / half, (eye_across.y - centre.y) / half,
                        (glm::dot(eye_now, axes_.travel) - near) / depth, 1.0);
      data.light_from_world[k] = glm::mat4(m);
      data.texel_metres[k] = float(texel);
      data.depth_metres[k] = float(depth);
      const TiledMap grid{centre - half, texel, resolution, tiles};
      for (uint32_t t = 0; t < tiles * tiles; ++t) tile_rects.push_back(grid.tile(t));
    }

    // Every unit's triangles, for the schedule; the draws of this frame's units only (a draw
    // costs more to build than a caster to count).
    std::vector<Unit> units(tile_rects.size());
    walk(tile_rects, [&](size_t t, uint32_t, const glm::dmat4&, const MeshRecord& mesh) {
      units[t].triangles += mesh.index_count / 3;
    });

    // This frame's units: the stale ones in order (finest level first) while they fit the budget;
    // every one after a reset.
    const uint32_t per_level = tiles * tiles;
    std::vector<uint32_t> due;
    uint64_t filled = 0;
    for (uint32_t u = 0; u < units.size(); ++u) {
      if (!(plan.stale[u / per_level] >> (u % per_level) & 1u)) continue;
      if (!plan.reset && !due.empty() && filled + units[u].triangles > plan.budget_triangles) {
        ++plan.pending;
        continue;
      }
      due.push_back(u);
      filled += units[u].triangles;
    }
    std::vector<LightRect> due_rects;
    for (uint32_t u : due) due_rects.push_back(tile_rects[u]);
    walk(due_rects, [&](size_t t, uint32_t index, const glm::dmat4& model, const MeshRecord& mesh) {
      Unit& unit = units[due[t]];
      unit.draws.push_back(draw_of(index, model, mesh));
      if (due[t] < per_level && (instances_[index].flags & kInstanceShadowOccluder)) {
        // The finest mesh's leading triangles, which every level the instance is drawn at has.
        const MeshRecord& finest = *mesh_at(instances_[index].primitive);
        GpuDraw occluder = draw_of(index, model, finest);
        occluder.index_count = finest.occluder_index_count / 3 * 3;
        if (occluder.index_count > 0) unit.occluders.push_back(occluder);
      }
    });
    for (uint32_t u : due) {
      sort_for_batching(units[u].draws);
      sort_for_batching(units[u].occluders);
    }
    std::vector<GpuDraw> all;
    for (uint32_t u = 0; u < units.size(); ++u) plan.unit_triangles[u] = units[u].triangles;
    for (uint32_t u : due) {
      plan.refreshed[u / per_level] |= 1u << (u % per_level);
      plan.unit_first_draw[u] = uint32_t(all.size());
      plan.unit_draws[u] = uint32_t(units[u].draws.size());
      plan.triangles += units[u].triangles;
      all.insert(all.end(), units[u].draws.begin(), units[u].draws.end());
    }
    for (uint32_t u : due) {
      if (u >= per_level) continue;
      plan.occluder_first_draw[u] = uint32_t(all.size());
      plan.occluder_draws[u] = uint32_t(units[u].occluders.size());
      all.insert(all.end(), units[u].occluders.begin(), units[u].occluders.end());
    }
    for (uint32_t k = 0; k < kDistantLevels; ++k)
      plan.complete[k] = (all_tiles(tiles) & ~plan.stale[k]) | plan.refreshed[k];
    plan.draws = uint32_t(all.size());
    for (uint32_t u : due)
      if (units[u].triangles > plan.budget_triangles) plan.over_budget = 1;
    for (uint32_t k = 0; k < kDistantLevels; ++k) data.refresh[k].z = int(plan.refreshed[k]);
    ctx_.store<GpuDistantLevels>("shadow.distant_data", {&data, 1});
    ctx_.store<DistantPlan>("shadow.distant_plan", {&plan, 1});
    ctx_.store<GpuDraw>("draws.shadow.distant", all);
  }

 private:
  static uint32_t all_tiles(uint32_t tiles) { return (1u << (tiles * tiles)) - 1u; }

  // The previous frame's record, or null when there is none to keep (frame 0, a cut, a frame
  // whose plan did not run).
  const DistantPlan* previous_plan() {
    const std::span<const uint8_t> bytes = ctx_.host(previous("shadow.distant_plan"));
    if (bytes.size() != sizeof(DistantPlan)) return nullptr;
    std::memcpy(&previous_, bytes.data(), sizeof(DistantPlan));
    return &previous_;
  }

  dvec3 eye() const { return dvec3(camera_.world[12], camera_.world[13], camera_.world[14]); }

  const MeshRecord* mesh_at(uint32_t index) const {
    if (index >= meshes_.size())
      throw GraphError("shadow.distant_plan: an instance names mesh " + std::to_string(index));
    return &meshes_[index];
  }

  // The coarsest level of the instance's mesh, or null when it casts no shadow here.
  const MeshRecord* caster_mesh(uint32_t index, const glm::dmat4& model) const {
    const InstanceRecord& r = instances_[index];
    if (r.material >= materials_.size()) return nullptr;
    const GpuMaterial& m = materials_[r.material];
    if (!casts_shadow(m)) return nullptr;
    const double determinant = glm::determinant(glm::dmat3(model));
    const MeshRecord* mesh = mesh_at(r.primitive);
    uint32_t steps = 0;
    while (mesh->coarser >= 0) {
      if (++steps > meshes_.size()) throw GraphError("shadow.distant_plan: mesh levels of detail form a cycle");
      mesh = mesh_at(uint32_t(mesh->coarser));
    }
    if (!std::isfinite(determinant) || determinant == 0.0 || mesh->index_count == 0) return nullptr;
    return mesh;
  }

  // World model matrix of a static instance.
  glm::dmat4 model_of(uint32_t index) const { return instance_model(instances_[index], camera_.time); }

  // Every static caster whose box, across the sun, meets one of `tiles`, through the hierarchy:
  // visit(tile, instance, model, mesh) for each tile it meets.
  template <typename Visit>
  void walk(const std::vector<LightRect>& tiles, Visit visit) const {
    visit_static_across_sun(hierarchy_, axes_, tiles, [&](uint32_t index) {
      const glm::dmat4 model = model_of(index);
      const MeshRecord* mesh = caster_mesh(index, model);
      if (!mesh) return;
      const LightRect box = across_sun(axes_, model, *mesh);
      for (size_t t = 0; t < tiles.size(); ++t)
        if (box.meets(tiles[t])) visit(t, index, model, *mesh);
    });
  }

  GpuDraw draw_of(uint32_t index, const glm::dmat4& world_model, const MeshRecord& mesh) const {
    glm::dmat4 model = world_model;
    model[3] -= glm::dvec4(eye(), 0.0);  // camera-relative, as every draw list
    return caster_draw(index, instances_[index], model, mesh);
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  GpuFrameConstants constants_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  Hierarchy hierarchy_;
  LightAxes axes_;
  DistantPlan previous_{};
};

}  // namespace

PassDecl shadow_distant_plan_pass() {
  return PassDecl("shadow.distant_plan", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("frame.constants", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read_previous("shadow.distant_plan", Use::host)
      .write("shadow.distant_data", Use::host, BufferDecl{kinds::buffer})
      .write("draws.shadow.distant", Use::host, BufferDecl{kinds::draw_list})
      .write("shadow.distant_plan", Use::host, BufferDecl{kinds::buffer})
      .layout("shadow.distant_data", distant_levels_schema())
      .layout("draws.shadow.distant", draw_schema())
      .layout("shadow.distant_plan", distant_plan_schema())
      .param(distant_shadow_resolution())
      .param_float("level0_metres", 256, 1, 100000,
                   "side of the finest level in metres (grown until the last level covers the map)")
      .param_int("tiles", 2, 1, kDistantMaxTilesPerSide, "tiles per side of a level: the unit of refresh")
      .param_int("budget_triangles", 500000, 0, 1e9,
                 "triangles shadow.distant draws per frame at most (a unit above it is drawn alone)")
      .flag("cache", true,
            "1: levels carry over from the previous frame and only stale units are redrawn; 0: every level "
            "drawn whole each frame")
      .needs("sun_above_horizon")
      .run([](PassContext& ctx) { DistantPlanner(ctx).run(); });
}

}  // namespace nightcap
