// cull.main (CPU): frustum culling of the scene's instances against the camera, and the draw
// lists of the geometry passes, sorted by material so texture bindings change least.
// Occlusion culling (a small CPU depth raster) comes with the geometry stage.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "passes/core/context.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {
namespace {

// Conservative: false only when all eight corners lie outside one clip plane.
bool outside_frustum(const glm::dmat4& clip_from_object, const float* lo, const float* hi) {
  int outside[5] = {0, 0, 0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec4 p(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2], 1.0);
    const glm::dvec4 c = clip_from_object * p;
    outside[0] += c.x < -c.w;
    outside[1] += c.x > c.w;
    outside[2] += c.y < -c.w;
    outside[3] += c.y > c.w;
    outside[4] += c.z > c.w;  // in front of the near plane (reversed-Z: z = znear, w = -z_view)
  }
  return std::any_of(std::begin(outside), std::end(outside), [](int n) { return n == 8; });
}

void cull(PassContext& ctx) {
  const CameraRecordGpu camera = host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0);
  const auto instances = host_records<InstanceRecord>(ctx.host("scene.instances"));
  const auto materials = host_records<GpuMaterial>(ctx.host("scene.materials"));
  glm::dmat4 world;
  std::memcpy(&world[0][0], camera.world, sizeof(camera.world));
  const glm::dvec3 eye = glm::dvec3(world[3]);
  const glm::dmat4 view_projection =
      reversed_z_projection(camera.yfov, double(camera.width) / camera.height, camera.znear) * relative_view(world);
  const bool frustum = ctx.param("frustum") != 0.0;

  std::vector<GpuDraw> prepass, gbuffer;
  for (uint32_t i = 0; i < instances.size(); ++i) {
    const InstanceRecord& r = instances[i];
    if (r.moving || r.index_count == 0 || r.material >= materials.size()) continue;
    glm::dmat4 model;
    std::memcpy(&model[0][0], r.world, sizeof(r.world));
    model[3] -= glm::dvec4(eye, 0.0);  // camera-relative, subtracted in double
    // A zero-scale transform covers no pixel and has no normal matrix.
    const double determinant = glm::determinant(glm::dmat3(model));
    if (!std::isfinite(determinant) || determinant == 0.0) continue;
    if (frustum && outside_frustum(view_projection * model, r.bounds_min, r.bounds_max)) continue;
    const GpuMaterial& m = materials[r.material];
    GpuDraw d{};
    d.model = glm::mat4(model);
    d.normal_matrix = glm::mat4(glm::transpose(glm::inverse(glm::dmat3(model))));
    d.first_index = r.first_index;
    d.index_count = r.index_count;
    d.vertex_offset = r.vertex_offset;
    d.material = r.material;
    d.stencil = uint32_t(m.textures2.z);
    d.instance = i;
    d.mirrored = determinant < 0.0;
    const glm::vec3 lo = glm::make_vec3(r.bounds_min), hi = glm::make_vec3(r.bounds_max);
    d.position_origin = glm::vec4(lo, 0.0f);
    d.position_step = glm::vec4(position_step(lo, hi), 0.0f);
    gbuffer.push_back(d);
    // Alpha-tested and blended surfaces do not occlude reliably: the prepass leaves them out.
    if (m.extra.z == float(AlphaMode::opaque)) prepass.push_back(d);
  }
  auto by_material = [](const GpuDraw& a, const GpuDraw& b) {
    return a.material != b.material ? a.material < b.material : a.instance < b.instance;
  };
  std::sort(prepass.begin(), prepass.end(), by_material);
  std::sort(gbuffer.begin(), gbuffer.end(), by_material);
  auto store = [&](const char* name, const std::vector<GpuDraw>& draws) {
    auto& out = ctx.output(name);
    out.resize(draws.size() * sizeof(GpuDraw));
    if (!draws.empty()) std::memcpy(out.data(), draws.data(), out.size());
  };
  store("draws.depth.prepass", prepass);
  store("draws.gbuffer.opaque", gbuffer);
}

}  // namespace

PassDecl cull_main_pass() {
  return PassDecl("cull.main", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.materials", Use::host)
      .write("draws.depth.prepass", Use::host, BufferDecl{ResourceKind::draw_list})
      .write("draws.gbuffer.opaque", Use::host, BufferDecl{ResourceKind::draw_list})
      .layout("draws.depth.prepass", draw_schema())
      .layout("draws.gbuffer.opaque", draw_schema())
      .param("frustum", 1, 0, 1, "1: drop instances outside the view frustum")
      .run(cull);
}

}  // namespace nightcap
