// shadow.topdown_plan (CPU): where the top-down map lies this frame, and whether shadow.topdown
// redraws it (frame.md's shadow.topdown [001]: the static scene seen from straight above, a
// height map, for the sky's visibility).
//
// The map: a square of `metres` around the camera in world x and z, `resolution` texels a side,
// its centre snapped to an eighth of its side, so it moves rarely (the camera must cross into
// another eighth) and always keeps at least 3/8 of its side on every side of the camera. Height:
// z = 0 at the static scene's top, 1 at its bottom (a metre of room each way), the same every
// frame; a texel holds the top of whatever static opaque surface covers it, or 1 (nothing).
//
// Refresh: the map is drawn whole when there is no history (frame 0, a camera cut), when its
// centre moved, or when its frame (side, resolution, height range) changed; otherwise it is
// carried over (TopdownRefresh says which). Static casters never change, so a still camera, or
// one inside the same eighth, redraws nothing after the first frame.
//
// Casters: the static opaque instances whose box meets the square (a texel of room), at their
// finest level of detail (the map serves points at any distance from the camera, and the finest
// level is what the camera's neighbourhood draws). Moving instances are left out: the map is
// kept for many frames.
#include <algorithm>
#include <cmath>

#include "passes/core/context.h"
#include "passes/core/previous_record.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"
#include "passes/shadow/topdown_layout.h"

namespace nightcap {
namespace {

using glm::dvec2;
using glm::dvec3;

// Straight down: across(p) is (x, z).
const LightAxes kDown{dvec3(1, 0, 0), dvec3(0, 0, 1), dvec3(0, -1, 0)};

class TopdownPlanner {
 public:
  explicit TopdownPlanner(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())) {}

  void run() {
    const uint32_t resolution = uint32_t(ctx_.param_int("resolution"));
    if (resolution % 8 != 0) throw GraphError("shadow.topdown_plan: resolution must be a multiple of 8");
    const double side = ctx_.param_float("metres"), texel = side / resolution;
    const dvec3 eye(camera_.world[12], camera_.world[13], camera_.world[14]);
    // The static scene's height range (a few metres around the eye when there is none).
    double top = eye.y + 1.0, bottom = eye.y - 1.0;
    if (!hierarchy_.static_order.empty()) {
      top = hierarchy_.nodes[0].bounds_max[1];
      bottom = hierarchy_.nodes[0].bounds_min[1];
    }
    top = std::ceil(top) + 1.0;
    bottom = std::floor(bottom) - 1.0;

    TopdownPlan plan{};
    plan.resolution = resolution;
    plan.side_metres = float(side);
    plan.top = float(top);
    plan.bottom = float(bottom);
    const double step = side / 8.0;
    const dvec2 centre = glm::floor(kDown.across(eye) / step) * step;
    const glm::ivec2 centre_texels(glm::round(centre / texel));
    plan.centre[0] = centre_texels.x;
    plan.centre[1] = centre_texels.y;
    const std::optional<TopdownPlan> before = previous_record<TopdownPlan>(ctx_, "shadow.topdown_plan");
    if (!before)
      plan.refresh = uint32_t(TopdownRefresh::no_history);
    else if (before->resolution != plan.resolution || before->side_metres != plan.side_metres ||
             before->top != plan.top || before->bottom != plan.bottom)
      plan.refresh = uint32_t(TopdownRefresh::changed);
    else if (before->centre[0] != plan.centre[0] || before->centre[1] != plan.centre[1])
      plan.refresh = uint32_t(TopdownRefresh::moved);

    // camera-relative p → ((p + eye).x − cx) / (side / 2), ((p + eye).z − cz) / (side / 2),
    // (top − (p + eye).y) / (top − bottom).
    const double half = 0.5 * side, depth = top - bottom;
    glm::dmat4 m(0.0);
    m[0][0] = 1.0 / half;
    m[2][1] = 1.0 / half;
    m[1][2] = -1.0 / depth;
    m[3] = glm::dvec4((eye.x - centre.x) / half, (eye.z - centre.y) / half, (top - eye.y) / depth, 1.0);
    GpuTopdown data{};
    data.map_from_world = glm::mat4(m);
    // A point looks up from `push_metres` off its surface, 2 texels at least (the lookup blends
    // the 4 texels around it: off its own wall's roof). Metres, not texels: what lies above a
    // point must not depend on the map's resolution (a sign 0.35 m off a wall is above a point
    // pushed 0.12 m, not one pushed 0.5 m).
    data.extent = glm::vec4(float(texel), float(depth), float(resolution),
                            float(std::max(ctx_.param_float("push_metres"), 2.0 * texel)));

    std::vector<GpuDraw> draws;
    if (plan.refresh != uint32_t(TopdownRefresh::kept)) {
      const LightRect square{centre - half - texel, centre + half + texel};
      visit_static_across_sun(hierarchy_, kDown, std::span<const LightRect>(&square, 1), [&](uint32_t index) {
        const InstanceRecord& r = instances_[index];
        if (r.material >= materials_.size() || !casts_shadow(materials_[r.material])) return;
        const glm::dmat4 model = instance_model(r, 0.0);
        const double determinant = glm::determinant(glm::dmat3(model));
        if (r.primitive >= meshes_.size())
          throw GraphError("shadow.topdown_plan: instance " + std::to_string(index) + " names mesh " +
                           std::to_string(r.primitive) + " of " + std::to_string(meshes_.size()));
        const MeshRecord& mesh = meshes_[r.primitive];
        if (!std::isfinite(determinant) || determinant == 0.0 || mesh.index_count == 0) return;
        if (!across_sun(kDown, model, mesh).meets(square)) return;
        glm::dmat4 relative = model;
        relative[3] -= glm::dvec4(eye, 0.0);  // camera-relative, as every draw list
        draws.push_back(caster_draw(index, r, relative, mesh));
        plan.triangles += mesh.index_count / 3;
      });
      sort_for_batching(draws);
    }
    plan.draws = uint32_t(draws.size());
    ctx_.store<GpuTopdown>("shadow.topdown_data", {&data, 1});
    ctx_.store<TopdownPlan>("shadow.topdown_plan", {&plan, 1});
    ctx_.store<GpuDraw>("draws.shadow.topdown", draws);
  }

 private:
  PassContext& ctx_;
  CameraRecordGpu camera_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  Hierarchy hierarchy_;
};

}  // namespace

PassDecl shadow_topdown_plan_pass() {
  return PassDecl("shadow.topdown_plan", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read_previous("shadow.topdown_plan", Use::host)
      .write("shadow.topdown_data", Use::host, BufferDecl{kinds::buffer})
      .write("draws.shadow.topdown", Use::host, BufferDecl{kinds::draw_list})
      .write("shadow.topdown_plan", Use::host, BufferDecl{kinds::buffer})
      .layout("shadow.topdown_data", topdown_schema())
      .layout("draws.shadow.topdown", draw_schema())
      .layout("shadow.topdown_plan", topdown_plan_schema())
      .param(topdown_resolution())
      .param_float("metres", 512.0, 16.0, 100000.0, "side of the top-down map's square around the camera")
      .param_float("push_metres", 0.5, 0.0, 10.0,
                   "how far off its surface, along the normal, a point looks up from (2 texels at least)")
      .run([](PassContext& ctx) { TopdownPlanner(ctx).run(); });
}

}  // namespace nightcap
