// shadow.local_plan (CPU): which spot lights get a shadow map this frame, their projections and
// their casters (frame.md section 1, shadow.local [004 §3]).
//
// Candidates: the spot lights of frame.lights, which frame.constants already limited to those
// lighting something in view (frustum and cull.main's occlusion buffer). A spot light is the
// first kind of local light with a map because one perspective map covers its cone; point
// lights would need six. Every spot light with a range casts: the scene format has no per-light
// switch yet. A spot with range 0 has no far plane and gets none (recorded as such).
// Selection: the `max_maps` candidates whose sphere of influence looks largest from the camera
// (range / distance), ties by index: a fixed number of maps per frame [004 §3], the lights
// whose shadows cover the most of the screen first. The others are dropped (recorded, reason
// over_budget) and lighting.tiled lights with them unshadowed.
//
// Casters: the opaque instances, static (through scene.hierarchy) and moving (where they are at
// this frame's time), whose box meets the box around the light's range, at their finest level
// of detail (a local light is near the surfaces it shadows). One draw list per map: its static
// casters, then its moving ones. The draws and the views they are drawn with are relative to the
// light's scene.lights position, not the camera, so a static caster's depth in a map is the same
// bits whatever the camera does.
//
// Caching across frames (`cache`, [004 §3]): shadow.local_static holds kLocalShadowSlices cache
// slots of static casters' depth, kept as history; shadow.local lays map k's slot down and draws
// the moving casters over it each frame. The plan reads its own record and views of the previous
// frame (empty on the first frame and after a camera cut) and follows each light by its
// scene.lights index (frame.lights is culled per frame, so its indices move). A selected light
// whose slot still holds it, under the same view bit for bit, reuses that slot: its static
// casters are not even listed. Any other selected light is refreshed (its static casters drawn
// into its old slot, an empty one, or the one idle longest), at most `max_refreshes` a frame.
// A light that needs a refresh past that budget is throttled: it gets no map this frame and
// lighting.tiled lights with it unshadowed, a map going to the next candidate instead. Such a
// light has no older map of its own to show (it is new to the cache, or its view changed), and
// another light's map is no answer; the largest on screen are refreshed first and the light is
// first in line next frame. The budget does not apply on a frame without history (the first,
// a cut): every map is new then, and a cut is where missing shadows would show most. A slot
// whose light has no map this frame keeps its depth (copied over from history, a layer copy
// each frame) until another light needs it or `keep_frames` frames have passed. With `cache` 0
// every map is refreshed every frame into slot k, without a budget. What each candidate and
// slot did, and why, is in the record (LocalShadowReason, LocalSlotState). The pass cannot see
// a history reset the graph makes for a resize: a renderer keeps shadow.local_static's
// resolution over a run.
//
// Never skipped: lighting.tiled reads its outputs whenever a light shades the frame (with no
// spot light in view they say that no light has a map), and it costs a pass over frame.lights.
//
// Moments: the `moments` parameter, recorded in shadow.local_data (counts.y) so that
// shadow.local_moments and lighting.tiled pick the same variant from the record
// (local_moments.cpp says why 4 by default).
//
// Projection: along the spot's axis, a square frustum whose half-angle is the outer cone (at
// most kMaxHalfAngle: a wider cone is shadowed only inside that; beyond it lighting.tiled reads
// it as lit), z forward from `near_metres` to the light's range. shadow.local_data holds it
// relative to the camera (for the lookups), shadow.local_views relative to the light.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "passes/core/context.h"
#include "passes/core/history_name.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/stage.h"

namespace nightcap {
namespace {

using glm::dvec3;

constexpr double kMaxHalfAngle = 1.3;  // radians, about 74.5°: a 149° map

class LocalPlanner {
 public:
  explicit LocalPlanner(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        lights_(host_records<GpuLight>(ctx.host("frame.lights"))),
        scene_lights_(host_records<LightRecord>(ctx.host("scene.lights"))),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())) {}

  void run() {
    const uint32_t max_maps = uint32_t(ctx_.param_int("max_maps"));
    const uint32_t max_refreshes = uint32_t(ctx_.param_int("max_refreshes"));
    const bool cache = ctx_.flag("cache");
    const double near = ctx_.param_float("near_metres");
    LocalShadowPlan before{};
    GpuLocalShadowViews views_before{};
    const bool history = read_history(before, views_before);
    LocalShadowPlan plan{};
    plan.max_maps = max_maps;
    plan.max_refreshes = max_refreshes;
    plan.cache = cache;
    plan.reset = !history;
    GpuLocalShadows data{};
    GpuLocalShadowViews views{};
    std::vector<int32_t> slots(std::max<size_t>(lights_.size(), 1), -1);

    // The slots as the previous frame left them; none with the cache off or without history.
    std::fill(std::begin(plan.slot_light), std::end(plan.slot_light), kLocalNoLight);
    if (cache && history)
      for (uint32_t s = 0; s < kLocalShadowSlices; ++s) {
        plan.slot_light[s] = before.slot_light[s];
        plan.slot_idle[s] = before.slot_idle[s];
      }

    struct Candidate {
      uint32_t light, scene;
      double score;
      bool bounded;
    };
    std::vector<Candidate> candidates;
    for (uint32_t i = 0; i < lights_.size(); ++i) {
      const GpuLight& l = lights_[i];
      if (uint32_t(l.position_type.w) != uint32_t(LightType::spot)) continue;
      const uint32_t scene = uint32_t(l.cos_inner.y);
      if (!(l.cos_inner.y >= 0.0f) || scene >= scene_lights_.size())
        throw GraphError("shadow.local_plan: frame.lights[" + std::to_string(i) + "] names scene light " +
                         std::to_string(l.cos_inner.y) + ", but scene.lights holds " +
                         std::to_string(scene_lights_.size()));
      const double range = l.color_range.w;
      const double distance = glm::length(dvec3(glm::vec3(l.position_type)));
      const bool bounded = range > near;
      candidates.push_back({i, scene, bounded ? range / std::max(distance, 1e-3) : 0.0, bounded});
    }
    std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      if (a.bounded != b.bounded) return a.bounded;
      return a.score > b.score;
    });
    plan.candidates = uint32_t(candidates.size());
    std::vector<GpuDraw> all;
    std::array<glm::mat4, kLocalShadowSlices> map_view{};
    std::array<uint32_t, kLocalShadowSlices> map_scene{}, map_state{};
    std::array<int32_t, kLocalShadowSlices> map_slot{};
    std::array<bool, kLocalShadowSlices> slot_taken{};
    for (uint32_t rank = 0; rank < candidates.size(); ++rank) {
      const Candidate& c = candidates[rank];
      LocalShadowReason reason = LocalShadowReason::unbounded_range;
      const GpuLight& l = lights_[c.light];
      const double far = l.color_range.w;
      glm::mat4 view(0.0f);
      int32_t own = -1;  // the slot holding this light's static depth from the previous frame
      LocalSlotState state = LocalSlotState::refreshed_cache_off;
      if (c.bounded && plan.maps >= max_maps) {
        reason = LocalShadowReason::over_budget;
      } else if (c.bounded) {
        view = glm::transpose(glm::mat4(projection(l, dvec3(0.0), near, far)));
        for (uint32_t s = 0; s < kLocalShadowSlices; ++s)
          if (plan.slot_light[s] == c.scene) own = int32_t(s);
        const bool same = own >= 0 && same_view(views_before, uint32_t(own), view);
        if (!cache) {
          state = LocalSlotState::refreshed_cache_off;
        } else if (!history) {
          state = LocalSlotState::refreshed_reset;
        } else if (same) {
          state = LocalSlotState::reused;
        } else {
          state = own >= 0 ? LocalSlotState::refreshed_changed : LocalSlotState::refreshed_new;
        }
        const bool refresh = state != LocalSlotState::reused;
        if (refresh && cache && history && plan.refreshed >= max_refreshes) {
          reason = LocalShadowReason::throttled;
          ++plan.throttled;
          // Its old depth is under another view: of no use now, the slot is free.
          if (own >= 0) plan.slot_light[own] = kLocalNoLight;
        } else {
          reason = refresh ? LocalShadowReason::refreshed : LocalShadowReason::reused;
          plan.refreshed += refresh;
          plan.reused += !refresh;
        }
      }
      if (rank < kLocalShadowRecorded) {
        plan.candidate_light[rank] = c.light;
        plan.candidate_reason[rank] = uint32_t(reason);
      }
      if (reason != LocalShadowReason::refreshed && reason != LocalShadowReason::reused) {
        ++plan.dropped;
        continue;
      }
      const uint32_t map = plan.maps++;
      const glm::mat4 clip = glm::transpose(glm::mat4(projection(l, dvec3(glm::vec3(l.position_type)), near, far)));
      data.clip_x[map] = clip[0];
      data.clip_y[map] = clip[1];
      data.clip_z[map] = clip[2];
      data.clip_w[map] = clip[3];
      data.depth_range[map] = glm::vec4(float(near), float(far), float(1.0 / (far - near)), float(c.light));
      slots[c.light] = int32_t(map);
      plan.slice_light[map] = c.light;
      map_view[map] = view;
      map_scene[map] = c.scene;
      map_state[map] = uint32_t(state);
      map_slot[map] = own;
      if (own >= 0) slot_taken[own] = true;
      plan.slice_first_draw[map] = uint32_t(all.size());
      const LightRecord& record = scene_lights_[c.scene];
      const dvec3 origin(record.position[0], record.position[1], record.position[2]);
      std::vector<GpuDraw> statics, moving;
      casters(origin - far, origin + far, state != LocalSlotState::reused, origin, statics, moving);
      for (std::vector<GpuDraw>* list : {&statics, &moving}) {
        sort_for_batching(*list);
        for (const GpuDraw& d : *list) plan.slice_triangles[map] += d.index_count / 3;
        all.insert(all.end(), list->begin(), list->end());
      }
      plan.slice_draws[map] = uint32_t(statics.size() + moving.size());
      plan.slice_moving_draws[map] = uint32_t(moving.size());
      plan.triangles += plan.slice_triangles[map];
    }
    // Slots for the refreshed maps without one of their own: an empty slot first, else the one
    // whose light has gone without a map the longest.
    for (uint32_t map = 0; map < plan.maps; ++map) {
      if (map_slot[map] >= 0) continue;
      int32_t pick = -1;
      for (uint32_t s = 0; s < kLocalShadowSlices; ++s) {
        if (slot_taken[s]) continue;
        if (plan.slot_light[s] == kLocalNoLight) {
          pick = int32_t(s);
          break;
        }
        if (pick < 0 || plan.slot_idle[s] > plan.slot_idle[pick]) pick = int32_t(s);
      }
      map_slot[map] = pick;
      slot_taken[pick] = true;
    }
    // A slot without a map this frame keeps its light for keep_frames frames: each kept slot
    // costs shadow.local_static a layer copy every frame.
    const uint32_t keep_frames = uint32_t(ctx_.param_int("keep_frames"));
    std::array<uint32_t, kLocalShadowSlices> slot_state{};
    for (uint32_t s = 0; s < kLocalShadowSlices; ++s) {
      if (plan.slot_light[s] == kLocalNoLight) continue;
      if (++plan.slot_idle[s] > keep_frames) {
        plan.slot_light[s] = kLocalNoLight;
        continue;
      }
      slot_state[s] = uint32_t(LocalSlotState::kept);
      const glm::mat4 kept(views_before.view_x[s], views_before.view_y[s], views_before.view_z[s],
                           views_before.view_w[s]);
      set_view(views, s, kept);
    }
    for (uint32_t map = 0; map < plan.maps; ++map) {
      const uint32_t s = uint32_t(map_slot[map]);
      plan.slice_slot[map] = s;
      plan.slot_light[s] = map_scene[map];
      plan.slot_idle[s] = 0;
      slot_state[s] = map_state[map];
      set_view(views, s, map_view[map]);
    }
    for (uint32_t s = 0; s < kLocalShadowSlices; ++s) {
      plan.slot_state[s] = slot_state[s];
      if (plan.slot_light[s] == kLocalNoLight) plan.slot_idle[s] = 0;
    }
    plan.draws = uint32_t(all.size());
    data.counts.x = plan.maps;
    data.counts.y = plan.moments = uint32_t(ctx_.param_int("moments"));
    // A map whose slot kept its static depth, and whose slot the previous frame mapped too, has
    // that map's moments but where moving casters are or were.
    std::fill(std::begin(plan.moments_from), std::end(plan.moments_from), -1);
    for (uint32_t map = 0; map < plan.maps; ++map) {
      if (map_state[map] != uint32_t(LocalSlotState::reused) || before.moments != plan.moments) continue;
      for (uint32_t earlier = 0; earlier < std::min(before.maps, kLocalShadowSlices); ++earlier)
        if (before.slice_slot[earlier] == plan.slice_slot[map]) plan.moments_from[map] = int32_t(earlier);
      if (plan.moments_from[map] < 0) continue;
      const LightRecord& record = scene_lights_[map_scene[map]];
      const GpuLight& l = lights_[plan.slice_light[map]];
      plan.moments_dirty[map] = moving_footprint(l, dvec3(record.position[0], record.position[1], record.position[2]),
                                                 near, double(l.color_range.w));
    }
    ctx_.store<GpuLocalShadows>("shadow.local_data", {&data, 1});
    ctx_.store<GpuLocalShadowViews>("shadow.local_views", {&views, 1});
    ctx_.store<int32_t>("shadow.local_slots", slots);
    ctx_.store<LocalShadowPlan>("shadow.local_plan", {&plan, 1});
    ctx_.store<GpuDraw>("draws.shadow.local", all);
  }

 private:
  // The previous frame's record and views; false when there are none (the first frame, a cut).
  bool read_history(LocalShadowPlan& plan, GpuLocalShadowViews& views) const {
    const std::span<const uint8_t> record = ctx_.host(previous("shadow.local_plan"));
    const std::span<const uint8_t> kept = ctx_.host(previous("shadow.local_views"));
    if (record.empty() && kept.empty()) return false;
    if (record.size() != sizeof(plan) || kept.size() != sizeof(views))
      throw GraphError("shadow.local_plan: the previous frame's record and views hold " +
                       std::to_string(record.size()) + " and " + std::to_string(kept.size()) + " bytes, not " +
                       std::to_string(sizeof(plan)) + " and " + std::to_string(sizeof(views)));
    std::memcpy(&plan, record.data(), sizeof(plan));
    std::memcpy(&views, kept.data(), sizeof(views));
    return true;
  }

  static bool same_view(const GpuLocalShadowViews& views, uint32_t slot, const glm::mat4& rows) {
    const glm::vec4 kept[4] = {views.view_x[slot], views.view_y[slot], views.view_z[slot], views.view_w[slot]};
    return std::memcmp(kept, &rows[0][0], sizeof(kept)) == 0;
  }

  static void set_view(GpuLocalShadowViews& views, uint32_t slot, const glm::mat4& rows) {
    views.view_x[slot] = rows[0];
    views.view_y[slot] = rows[1];
    views.view_z[slot] = rows[2];
    views.view_w[slot] = rows[3];
  }

  // World relative to `position` (the light's, relative to some origin) → the map's clip space
  // (local_layout.h).
  static glm::dmat4 projection(const GpuLight& l, const dvec3& position, double near, double far) {
    const dvec3 forward = glm::normalize(dvec3(glm::vec3(l.direction_cos_outer)));
    const dvec3 helper = std::abs(forward.y) < 0.99 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
    const dvec3 right = glm::normalize(glm::cross(helper, forward));
    const dvec3 up = glm::cross(forward, right);
    const double cone = std::acos(std::clamp(double(l.direction_cos_outer.w), -1.0, 1.0));
    const double scale = 1.0 / std::tan(std::clamp(cone, 0.01, kMaxHalfAngle));
    const double a = far / (far - near), b = -far * near / (far - near);
    glm::dmat4 m(0.0);
    for (int k = 0; k < 3; ++k) {
      m[k][0] = right[k] * scale;
      m[k][1] = up[k] * scale;
      m[k][2] = forward[k] * a;
      m[k][3] = forward[k];
    }
    m[3] = glm::dvec4(-glm::dot(position, right) * scale, -glm::dot(position, up) * scale,
                      -glm::dot(position, forward) * a + b, -glm::dot(position, forward));
    return m;
  }

  const MeshRecord* caster_mesh(uint32_t index) const {
    const InstanceRecord& r = instances_[index];
    if (r.material >= materials_.size()) return nullptr;
    const GpuMaterial& m = materials_[r.material];
    if (!casts_shadow(m)) return nullptr;
    if (r.primitive >= meshes_.size())
      throw GraphError("shadow.local_plan: an instance names mesh " + std::to_string(r.primitive));
    const MeshRecord* mesh = &meshes_[r.primitive];
    return mesh->index_count == 0 ? nullptr : mesh;
  }

  glm::dmat4 model_of(uint32_t index, double time) const { return instance_model(instances_[index], time); }
  glm::dmat4 model_of(uint32_t index) const { return model_of(index, camera_.time); }

  // World box of the instance's mesh at `time`; false when it casts nothing.
  bool world_box(uint32_t index, double time, dvec3& lo, dvec3& hi) const {
    const MeshRecord* mesh = caster_mesh(index);
    if (!mesh) return false;
    const glm::dmat4 model = model_of(index, time);
    const double determinant = glm::determinant(glm::dmat3(model));
    if (!std::isfinite(determinant) || determinant == 0.0) return false;
    lo = dvec3(INFINITY);
    hi = dvec3(-INFINITY);
    for (int c = 0; c < 8; ++c) {
      const dvec3 p(model * glm::dvec4(c & 1 ? mesh->bounds_max[0] : mesh->bounds_min[0],
                                       c & 2 ? mesh->bounds_max[1] : mesh->bounds_min[1],
                                       c & 4 ? mesh->bounds_max[2] : mesh->bounds_min[2], 1.0));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    return true;
  }

  // The NDC rectangle (x0, y0, x1, y1) of the map of light `l` at world `origin` that holds every
  // moving caster meeting its range, this frame and the one before; x0 > x1 when there is none,
  // the whole map when one reaches behind the light.
  glm::vec4 moving_footprint(const GpuLight& l, const dvec3& origin, double near, double far) const {
    const glm::dmat4 view = projection(l, dvec3(0.0), near, far);
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (uint32_t index : hierarchy_.moving)
      for (const double time : {camera_.time, camera_.time - camera_.time_step}) {
        dvec3 blo, bhi;
        if (!world_box(index, time, blo, bhi) || !meets(blo, bhi, origin - far, origin + far)) continue;
        for (int c = 0; c < 8; ++c) {
          const glm::dvec4 clip =
              view *
              glm::dvec4(dvec3(c & 1 ? bhi.x : blo.x, c & 2 ? bhi.y : blo.y, c & 4 ? bhi.z : blo.z) - origin, 1.0);
          if (!(clip.w > near * 0.5)) return glm::vec4(-1.0f, -1.0f, 1.0f, 1.0f);
          lo = glm::min(lo, glm::dvec2(clip) / clip.w);
          hi = glm::max(hi, glm::dvec2(clip) / clip.w);
        }
      }
    if (!(lo.x <= hi.x)) return glm::vec4(1.0f, 1.0f, -1.0f, -1.0f);
    return glm::vec4(glm::clamp(glm::dvec4(lo, hi), -2.0, 2.0));
  }

  static bool meets(const dvec3& lo, const dvec3& hi, const dvec3& olo, const dvec3& ohi) {
    return glm::all(glm::lessThanEqual(lo, ohi)) && glm::all(glm::lessThanEqual(olo, hi));
  }

  // The draws, relative to `origin`, of the opaque instances whose world box meets [lo, hi]:
  // static ones through the hierarchy (when `with_statics`), and the moving ones.
  void casters(const dvec3& lo, const dvec3& hi, bool with_statics, const dvec3& origin, std::vector<GpuDraw>& statics,
               std::vector<GpuDraw>& moving) const {
    std::vector<GpuDraw>* found = &statics;
    auto consider = [&](uint32_t index) {
      const MeshRecord* mesh = caster_mesh(index);
      if (!mesh) return;
      const glm::dmat4 model = model_of(index);
      if (!std::isfinite(glm::determinant(glm::dmat3(model))) || glm::determinant(glm::dmat3(model)) == 0.0) return;
      dvec3 blo(INFINITY), bhi(-INFINITY);
      for (int c = 0; c < 8; ++c) {
        const dvec3 p(model * glm::dvec4(c & 1 ? mesh->bounds_max[0] : mesh->bounds_min[0],
                                         c & 2 ? mesh->bounds_max[1] : mesh->bounds_min[1],
                                         c & 4 ? mesh->bounds_max[2] : mesh->bounds_min[2], 1.0));
        blo = glm::min(blo, p);
        bhi = glm::max(bhi, p);
      }
      if (!meets(blo, bhi, lo, hi)) return;
      glm::dmat4 relative = model;
      relative[3] -= glm::dvec4(origin, 0.0);
      found->push_back(caster_draw(index, instances_[index], relative, *mesh));
    };
    std::vector<uint32_t> stack;
    if (with_statics && !hierarchy_.static_order.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const HierarchyNode& node = hierarchy_.nodes[stack.back()];
      stack.pop_back();
      if (!meets(dvec3(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]),
                 dvec3(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]), lo, hi))
        continue;
      if (node.count == 0) {
        stack.push_back(node.first + 1);
        stack.push_back(node.first);
        continue;
      }
      for (uint32_t k = node.first; k < node.first + node.count; ++k) consider(hierarchy_.static_order[k]);
    }
    found = &moving;
    for (uint32_t index : hierarchy_.moving) consider(index);
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  std::vector<GpuLight> lights_;
  std::vector<LightRecord> scene_lights_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  Hierarchy hierarchy_;
};

}  // namespace

PassDecl shadow_local_plan_pass() {
  return PassDecl("shadow.local_plan", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("frame.lights", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read("scene.lights", Use::host)
      .read_previous("shadow.local_plan", Use::host)
      .read_previous("shadow.local_views", Use::host)
      .write("shadow.local_data", Use::host, BufferDecl{kinds::buffer})
      .write("shadow.local_views", Use::host, BufferDecl{kinds::buffer})
      .write("shadow.local_slots", Use::host, BufferDecl{kinds::buffer})
      .write("draws.shadow.local", Use::host, BufferDecl{kinds::draw_list})
      .write("shadow.local_plan", Use::host, BufferDecl{kinds::buffer})
      .layout("shadow.local_data", local_shadows_schema())
      .layout("shadow.local_views", local_shadow_views_schema())
      .layout("draws.shadow.local", draw_schema())
      .layout("shadow.local_plan", local_shadow_plan_schema())
      .param_int("max_maps", 8, 0, kLocalShadowSlices, "spot lights with a shadow map per frame at most")
      .param_float("near_metres", 0.05, 0.001, 10, "the maps' near plane: casters closer to the light cast nothing")
      .choice("moments", 4, numbered_choices(std::array<uint32_t, 2>{2, 4}),
              "moments per texel of shadow.local_moments: 4, moment shadow maps (Hamburger 4MSM); 2, variance "
              "shadow maps (frame.md's; leaks under stacked occluders)")
      .param_int("max_refreshes", 4, 0, kLocalShadowSlices,
                 "cache slots whose static casters are drawn per frame at most, with the cache on and history (a light "
                 "needing one past that gets no map this frame)")
      .param_int("keep_frames", 60, 0, 100000,
                 "frames a cache slot keeps the static depth of a light without a map (copied each frame) before it is "
                 "freed")
      .flag("cache", true,
            "1: a map whose light and view are the previous frame's keeps its static casters' depth "
            "(shadow.local_static) and draws only the moving ones; 0: everything drawn each frame")
      .run([](PassContext& ctx) { LocalPlanner(ctx).run(); });
}

}  // namespace nightcap
