// probes.cull (CPU): what each captured probe's faces draw, and the local lights its capture is
// lit by (probes.plan chose the probes and their face views).
//
// Draws: the static instances whose box centre lies within `capture_metres` of the probe and
// within their level's draw distance from it, the level chosen by that distance as cull.main
// chooses it from the camera; each is listed for every face whose frustum its box meets
// (probes.views), sorted as cull.main sorts a list so equal neighbours batch. Not drawn: moving
// instances (a capture is kept for many frames: a passing car would stay in it) and decals. No
// occlusion culling: a face is 64 texels a side, what it would save is small.
//
// Lights: the scene's local lights (point, spot and tube; its directional lights other than the
// sun are not drawn into captures) that reach within `capture_metres` of the probe, the `lights`
// brightest at the probe (luminous intensity over the squared distance, at least a metre) kept,
// ties by index. They are unshadowed in the capture.
//
// probes.face_draws holds each face's range of draws.probes and its capture's range of
// probes.lights (GpuProbeFace). Without a plan (none, or disabled) every list is empty.
#include <algorithm>
#include <cstring>

#include "passes/core/context.h"
#include "passes/frame/constants.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/level_of_detail.h"
#include "passes/frame/occlusion_buffer.h"
#include "passes/frame/scene_resources.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "passes/scene/scene.h"
#include "passes/shadow/caster_draw.h"

namespace nightcap {
namespace {

glm::dvec3 world_position(const double (&p)[3]) { return {p[0], p[1], p[2]}; }

// The distance from `point` to the box [lo, hi] (0 inside).
double distance_to_box(const glm::dvec3& point, const glm::dvec3& lo, const glm::dvec3& hi) {
  return glm::length(point - glm::clamp(point, lo, hi));
}

// The order of a face's draws, as cull.main's lists: (emissive or ground class, material), (mesh,
// instance).
struct FaceDraw {
  uint64_t major, minor;
  GpuDraw draw;
};

class ProbeCuller {
 public:
  explicit ProbeCuller(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        plan_(read_probe_plan(ctx.host("probes.plan"))),
        views_(host_records<GpuView>(ctx.host("probes.views"))),
        probes_(host_view<ProbeRecord>(ctx.host("scene.probes"))),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        lights_(host_view<LightRecord>(ctx.host("scene.lights"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())),
        reach_(ctx.param_float("capture_metres")) {
    eye_ = glm::dvec3(camera_.world[12], camera_.world[13], camera_.world[14]);
    if (plan_.captured > kProbeSlots || views_.size() != size_t(plan_.captured) * 6)
      throw GraphError("probes.cull: probes.plan captures " + std::to_string(plan_.captured) +
                       " probes but probes.views holds " + std::to_string(views_.size()) + " views");
  }

  void run() {
    std::vector<GpuProbeFace> faces;
    for (uint32_t k = 0; k < plan_.captured; ++k) {
      const uint32_t slot = plan_.capture_slot[k];
      if (slot >= kProbeSlots || plan_.slot_probe[slot] >= probes_.size())
        throw GraphError("probes.cull: probes.plan's capture " + std::to_string(k) + " names no probe of scene.probes");
      const glm::dvec3 probe = world_position(probes_[plan_.slot_probe[slot]].position);
      const uint32_t first_light = uint32_t(lights_out_.size());
      choose_lights(probe);
      std::array<std::vector<FaceDraw>, 6> lists;
      if (!hierarchy_.static_order.empty()) visit(0, probe, k, lists);
      for (uint32_t f = 0; f < 6; ++f) {
        std::sort(lists[f].begin(), lists[f].end(), [](const FaceDraw& a, const FaceDraw& b) {
          return std::tie(a.major, a.minor) < std::tie(b.major, b.minor);
        });
        faces.push_back({uint32_t(draws_.size()), uint32_t(lists[f].size()), first_light,
                         uint32_t(lights_out_.size()) - first_light});
        for (const FaceDraw& d : lists[f]) draws_.push_back(d.draw);
      }
    }
    ctx_.store<GpuDraw>("draws.probes", draws_);
    ctx_.store<GpuProbeFace>("probes.face_draws", faces);
    ctx_.store<GpuLight>("probes.lights", lights_out_);
  }

 private:
  void visit(uint32_t index, const glm::dvec3& probe, uint32_t capture, std::array<std::vector<FaceDraw>, 6>& lists) {
    const HierarchyNode& node = hierarchy_.nodes[index];
    const glm::dvec3 lo(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]);
    const glm::dvec3 hi(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]);
    if (distance_to_box(probe, lo, hi) > reach_) return;
    if (node.count == 0) {
      visit(node.first, probe, capture, lists);
      visit(node.first + 1, probe, capture, lists);
      return;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k)
      consider(hierarchy_.static_order[k], probe, capture, lists);
  }

  void consider(uint32_t index, const glm::dvec3& probe, uint32_t capture,
                std::array<std::vector<FaceDraw>, 6>& lists) {
    const InstanceRecord& r = instances_[index];
    if (r.material >= materials_.size() || (int(materials_[r.material].extra.w) & 4) != 0) return;  // decal
    // Static: where it stands at time 0, relative to the camera (subtracted in double).
    glm::dmat4 model = instance_model(r, 0.0);
    model[3] -= glm::dvec4(eye_, 0.0);
    const double determinant = glm::determinant(glm::dmat3(model));
    if (!std::isfinite(determinant) || determinant == 0.0) return;
    const MeshRecord& finest = *mesh_at(r.primitive, index);
    const double distance = glm::length(box_centre(model, finest) - (probe - eye_));
    if (distance > reach_) return;
    const LevelOfDetail level = level_of_detail(finest, distance, meshes_.size(), "probes.cull",
                                                [&](uint32_t coarser) { return mesh_at(coarser, index); });
    const MeshRecord* mesh = level.mesh;
    if (!level.drawn || mesh->index_count == 0) return;
    const GpuMaterial& m = materials_[r.material];
    const uint32_t stencil_class = uint32_t(m.textures2.z);
    const uint64_t draw_class = draw_order_class(m);
    const glm::dvec3 lo(mesh->bounds_min[0], mesh->bounds_min[1], mesh->bounds_min[2]);
    const glm::dvec3 hi(mesh->bounds_max[0], mesh->bounds_max[1], mesh->bounds_max[2]);
    for (uint32_t f = 0; f < 6; ++f) {
      const uint32_t view = capture * 6 + f;
      glm::dvec4 corners[8];
      box_corners(glm::dmat4(views_[view].view_projection) * model, lo, hi, corners);
      if (outside_frustum(corners)) continue;
      GpuDraw d = caster_draw(index, r, model, *mesh);
      d.stencil = stencil_class;
      d.view = view;
      lists[f].push_back({draw_class << 32 | r.material, uint64_t(mesh->first_index) << 32 | index, d});
    }
  }

  const MeshRecord* mesh_at(uint32_t index, uint32_t instance) const {
    if (index >= meshes_.size())
      throw GraphError("probes.cull: instance " + std::to_string(instance) + " names mesh " + std::to_string(index) +
                       " of " + std::to_string(meshes_.size()));
    return &meshes_[index];
  }

  void choose_lights(const glm::dvec3& probe) {
    struct Candidate {
      double score;
      uint32_t index;
    };
    std::vector<Candidate> found;
    for (uint32_t i = 0; i < lights_.size(); ++i) {
      const LightRecord& l = lights_[i];
      if (l.type == uint32_t(LightType::directional)) continue;
      const glm::dvec3 a = world_position(l.position);
      const glm::dvec3 b = l.type == uint32_t(LightType::tube) ? world_position(l.end) : a;
      const glm::dvec3 ab = b - a;
      const double t = glm::dot(ab, ab) > 0 ? glm::clamp(glm::dot(probe - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
      const double distance = glm::length(probe - (a + ab * t));
      if (l.range > 0.0f && distance > double(l.range) + reach_) continue;
      const double luminance = (0.2126 * l.color[0] + 0.7152 * l.color[1] + 0.0722 * l.color[2]) * double(l.intensity);
      found.push_back({luminance / std::max(distance * distance, 1.0), i});
    }
    std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) {
      return x.score != y.score ? x.score > y.score : x.index < y.index;
    });
    found.resize(std::min(found.size(), size_t(ctx_.param_int("lights"))));
    std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) { return x.index < y.index; });
    for (const Candidate& c : found) lights_out_.push_back(relative_light(lights_[c.index], c.index, eye_));
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  ProbePlan plan_;
  std::vector<GpuView> views_;
  std::span<const ProbeRecord> probes_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  std::span<const LightRecord> lights_;
  Hierarchy hierarchy_;
  double reach_;
  glm::dvec3 eye_{0.0};
  std::vector<GpuDraw> draws_;
  std::vector<GpuLight> lights_out_;
};

}  // namespace

PassDecl probes_cull_pass() {
  return PassDecl("probes.cull", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("probes.plan", Use::host)
      .read("probes.views", Use::host)
      .read("scene.probes", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read("scene.lights", Use::host)
      .write("draws.probes", Use::host, BufferDecl{kinds::draw_list})
      .write("probes.face_draws", Use::host, BufferDecl{kinds::buffer})
      .write("probes.lights", Use::host, BufferDecl{kinds::buffer})
      .layout("draws.probes", draw_schema())
      .layout("probes.face_draws", probe_face_schema())
      .layout("probes.lights", light_schema())
      .param_float("capture_metres", 200.0, 1.0, 10000.0,
                   "instances and lights within this distance of a probe are drawn into its capture")
      .param_int("lights", 16, 0, 256, "local lights lighting a capture at most, the brightest at the probe")
      .run([](PassContext& ctx) { ProbeCuller(ctx).run(); });
}

}  // namespace nightcap
