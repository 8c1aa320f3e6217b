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
// of detail (a local light is near the surfaces it shadows). One draw list per map.
//
// Not done: caching. Every selected map is redrawn every frame; the static casters' depth is
// not kept across frames as history, and there is no throttled refresh under a budget. The
// record's `maps` are therefore all refreshed.
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
// it as lit), z forward from `near_metres` to the light's range.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "passes/core/context.h"
#include "passes/cull/hierarchy.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/local_layout.h"

namespace nightcap {
namespace {

using glm::dvec3;

constexpr double kMaxHalfAngle = 1.3;  // radians, about 74.5°: a 149° map

struct Caster {
  uint32_t instance;
  glm::dmat4 model;  // world
  const MeshRecord* mesh;
};

class LocalPlanner {
 public:
  explicit LocalPlanner(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        lights_(host_records<GpuLight>(ctx.host("frame.lights"))),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())) {}

  void run() {
    const uint32_t max_maps = uint32_t(ctx_.param("max_maps"));
    const double near = ctx_.param("near_metres");
    LocalShadowPlan plan{};
    plan.max_maps = max_maps;
    GpuLocalShadows data{};
    std::vector<int32_t> slots(std::max<size_t>(lights_.size(), 1), -1);

    struct Candidate {
      uint32_t light;
      double score;
      bool bounded;
    };
    std::vector<Candidate> candidates;
    for (uint32_t i = 0; i < lights_.size(); ++i) {
      const GpuLight& l = lights_[i];
      if (uint32_t(l.position_type.w) != uint32_t(LightType::spot)) continue;
      const double range = l.color_range.w;
      const double distance = glm::length(dvec3(glm::vec3(l.position_type)));
      const bool bounded = range > near;
      candidates.push_back({i, bounded ? range / std::max(distance, 1e-3) : 0.0, bounded});
    }
    std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      if (a.bounded != b.bounded) return a.bounded;
      return a.score > b.score;
    });
    plan.candidates = uint32_t(candidates.size());
    std::vector<GpuDraw> all;
    for (uint32_t rank = 0; rank < candidates.size(); ++rank) {
      const Candidate& c = candidates[rank];
      const bool selected = c.bounded && plan.maps < max_maps;
      if (rank < kLocalShadowRecorded) {
        plan.candidate_light[rank] = c.light;
        plan.candidate_reason[rank] = uint32_t(!c.bounded ? LocalShadowReason::unbounded_range
                                               : selected ? LocalShadowReason::selected
                                                          : LocalShadowReason::over_budget);
      }
      if (!selected) {
        ++plan.dropped;
        continue;
      }
      const uint32_t slice = plan.maps++;
      const GpuLight& l = lights_[c.light];
      const double far = l.color_range.w;
      const glm::mat4 clip = glm::transpose(glm::mat4(projection(l, near, far)));
      data.clip_x[slice] = clip[0];
      data.clip_y[slice] = clip[1];
      data.clip_z[slice] = clip[2];
      data.clip_w[slice] = clip[3];
      data.depth_range[slice] = glm::vec4(float(near), float(far), float(1.0 / (far - near)), float(c.light));
      slots[c.light] = int32_t(slice);
      plan.slice_light[slice] = c.light;
      plan.slice_first_draw[slice] = uint32_t(all.size());
      std::vector<GpuDraw> draws;
      const dvec3 centre = eye() + dvec3(glm::vec3(l.position_type));
      for (const Caster& caster : casters(centre - far, centre + far)) {
        draws.push_back(draw_of(caster));
        plan.slice_triangles[slice] += caster.mesh->index_count / 3;
      }
      std::sort(draws.begin(), draws.end(), [](const GpuDraw& a, const GpuDraw& b) {
        if (a.material != b.material) return a.material < b.material;
        if (a.first_index != b.first_index) return a.first_index < b.first_index;
        return a.instance < b.instance;
      });
      plan.slice_draws[slice] = uint32_t(draws.size());
      plan.triangles += plan.slice_triangles[slice];
      all.insert(all.end(), draws.begin(), draws.end());
    }
    plan.draws = uint32_t(all.size());
    data.counts.x = plan.maps;
    data.counts.y = uint32_t(ctx_.param("moments"));
    if (data.counts.y != 2 && data.counts.y != 4)
      throw GraphError("shadow.local_plan: moments is 2 or 4, not " + std::to_string(data.counts.y));
    store("shadow.local_data", &data, sizeof(data));
    store("shadow.local_slots", slots.data(), slots.size() * sizeof(int32_t));
    store("shadow.local_plan", &plan, sizeof(plan));
    store("draws.shadow.local", all.data(), all.size() * sizeof(GpuDraw));
  }

 private:
  dvec3 eye() const { return dvec3(camera_.world[12], camera_.world[13], camera_.world[14]); }

  // Camera-relative world → the map's clip space (local_layout.h).
  static glm::dmat4 projection(const GpuLight& l, double near, double far) {
    const dvec3 position = dvec3(glm::vec3(l.position_type));
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

  void store(const char* name, const void* bytes, size_t size) {
    auto& out = ctx_.output(name);
    out.resize(size);
    if (size) std::memcpy(out.data(), bytes, size);
  }

  const MeshRecord* caster_mesh(uint32_t index) const {
    const InstanceRecord& r = instances_[index];
    if (r.material >= materials_.size()) return nullptr;
    const GpuMaterial& m = materials_[r.material];
    if (m.extra.z != float(AlphaMode::opaque) || (int(m.extra.w) & 4) != 0) return nullptr;
    if (r.primitive >= meshes_.size())
      throw GraphError("shadow.local_plan: an instance names mesh " + std::to_string(r.primitive));
    const MeshRecord* mesh = &meshes_[r.primitive];
    return mesh->index_count == 0 ? nullptr : mesh;
  }

  glm::dmat4 model_of(uint32_t index) const { return instance_model(instances_[index], camera_.time); }

  static bool meets(const dvec3& lo, const dvec3& hi, const dvec3& olo, const dvec3& ohi) {
    return glm::all(glm::lessThanEqual(lo, ohi)) && glm::all(glm::lessThanEqual(olo, hi));
  }

  // The opaque instances whose world box meets [lo, hi]: static ones through the hierarchy, then
  // the moving ones.
  std::vector<Caster> casters(const dvec3& lo, const dvec3& hi) const {
    std::vector<Caster> found;
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
      if (meets(blo, bhi, lo, hi)) found.push_back({index, model, mesh});
    };
    std::vector<uint32_t> stack;
    if (!hierarchy_.static_order.empty()) stack.push_back(0);
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
    for (uint32_t index : hierarchy_.moving) consider(index);
    return found;
  }

  GpuDraw draw_of(const Caster& caster) const {
    glm::dmat4 model = caster.model;
    model[3] -= glm::dvec4(eye(), 0.0);  // camera-relative, as every draw list
    return caster_draw(caster.instance, instances_[caster.instance], model, *caster.mesh);
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  std::vector<GpuLight> lights_;
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
      .write("shadow.local_data", Use::host, BufferDecl{ResourceKind::buffer})
      .write("shadow.local_slots", Use::host, BufferDecl{ResourceKind::buffer})
      .write("draws.shadow.local", Use::host, BufferDecl{ResourceKind::draw_list})
      .write("shadow.local_plan", Use::host, BufferDecl{ResourceKind::buffer})
      .layout("shadow.local_data", local_shadows_schema())
      .layout("draws.shadow.local", draw_schema())
      .layout("shadow.local_plan", local_shadow_plan_schema())
      .param("max_maps", 8, 0, kLocalShadowSlices, "spot lights with a shadow map per frame at most")
      .param("near_metres", 0.05, 0.001, 10, "the maps' near plane: casters closer to the light cast nothing")
      .param("moments", 4, 2, 4,
             "moments per texel of shadow.local_moments: 4, moment shadow maps (Hamburger 4MSM); 2, variance "
             "shadow maps (frame.md's; leaks under stacked occluders)")
      .run([](PassContext& ctx) { LocalPlanner(ctx).run(); });
}

}  // namespace nightcap
