// frame.constants (CPU): the camera and lights turned into the per-frame constants, the camera's
// view (frame.views[0], with TAA's jitter of this frame: passes/frame/jitter.h) and the
// camera-relative light list every shading pass reads. Doubles in, floats out, so world
// coordinates of thousands of metres lose nothing before the subtraction.
#include <algorithm>
#include <cstring>

#include "passes/core/context.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/constants.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/jitter.h"
#include "passes/frame/occlusion_buffer.h"
#include "passes/frame/scene_resources.h"
#include "passes/frame/view.h"

namespace nightcap {
namespace {

void build_constants(PassContext& ctx) {
  const CameraRecordGpu camera = host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0);
  const auto lights = host_records<LightRecord>(ctx.host("scene.lights"));
  glm::dmat4 world, previous;
  std::memcpy(&world[0][0], camera.world, sizeof(camera.world));
  std::memcpy(&previous[0][0], camera.previous_world, sizeof(camera.previous_world));
  const double aspect = double(camera.width) / camera.height;
  const glm::dvec3 eye = glm::dvec3(world[3]);

  const uint32_t supersample = uint32_t(ctx.param_int("supersample"));
  const glm::dvec2 jitter = supersample > 0       ? supersample_offset(camera.frame_index, supersample)
                            : ctx.flag("enabled") ? taa_jitter(camera.frame_index)
                                                  : glm::dvec2(0.0);
  const GpuView camera_view =
      perspective_view({.orientation = glm::dmat3(world),
                        .yfov = camera.yfov,
                        .znear = camera.znear,
                        .width = camera.width,
                        .height = camera.height,
                        .jitter = jitter},
                       previous_relative_view_projection(previous, world, camera.yfov, aspect, camera.znear));
  GpuFrameConstants c{};
  c.camera_world = glm::vec4(glm::vec3(eye), 1.0f);
  c.timing = {float(camera.time), float(camera.time_step), 0.0f, 0.0f};

  // A local light whose range box is outside the frustum or wholly behind cull.main's occluders
  // lights no visible surface: its window ends at its range, so dropping it changes no pixel.
  const OcclusionBuffer occlusion = OcclusionBuffer::from_record(ctx.host("cull.occlusion"));
  const glm::dmat4 clip_from_relative = reversed_z_projection(camera.yfov, aspect, camera.znear) * relative_view(world);
  auto lights_nothing_visible = [&](const LightRecord& l) {
    if (!(l.range > 0.0f)) return false;
    const glm::dvec3 start = glm::dvec3(l.position[0], l.position[1], l.position[2]) - eye;
    // Point and spot lights reach from their position; a tube from every point of its segment.
    const glm::dvec3 end = l.type == uint32_t(LightType::tube) ? glm::dvec3(l.end[0], l.end[1], l.end[2]) - eye : start;
    glm::dvec3 lo = glm::min(start, end), hi = glm::max(start, end);
    lo -= glm::dvec3(l.range);
    hi += glm::dvec3(l.range);
    glm::dvec4 corners[8];
    for (int k = 0; k < 8; ++k)
      corners[k] = clip_from_relative * glm::dvec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1.0);
    return outside_frustum(corners) || occlusion.hidden(corners);
  };

  std::vector<GpuLight> list;
  bool has_sun = false;
  uint32_t dropped = 0;
  for (uint32_t index = 0; index < lights.size(); ++index) {
    const LightRecord& l = lights[index];
    const glm::vec3 radiance = glm::vec3(l.color[0], l.color[1], l.color[2]) * l.intensity;
    const glm::vec3 direction = glm::normalize(glm::vec3(l.direction[0], l.direction[1], l.direction[2]));
    if (l.type == uint32_t(LightType::directional) && !has_sun) {
      // The first directional light is the sun (or moon) the shadow passes will follow.
      has_sun = true;
      c.sun_direction = glm::vec4(direction, 1.0f);
      c.sun_radiance = glm::vec4(radiance, 0.0f);
      continue;
    }
    if (l.type != uint32_t(LightType::directional) && lights_nothing_visible(l)) {
      ++dropped;
      continue;
    }
    list.push_back(relative_light(l, index, eye));
  }
  // Grouped so that a shader loops over each kind of light apart: lavapipe runs both sides of a
  // branch, so one loop over mixed kinds pays for the costliest kind at every light.
  auto group = [](const GpuLight& g) {
    const uint32_t type = uint32_t(g.position_type.w);
    if (type == uint32_t(LightType::directional)) return 0;
    if (type == uint32_t(LightType::tube)) return 3;
    return type == uint32_t(LightType::point) && g.end_radius.w > 0 ? 2 : 1;
  };
  std::stable_sort(list.begin(), list.end(), [&](const GpuLight& a, const GpuLight& b) { return group(a) < group(b); });
  uint32_t first[4] = {};
  for (int k = 1; k < 4; ++k)
    first[k] = uint32_t(std::find_if(list.begin(), list.end(), [&](const GpuLight& g) { return group(g) >= k; }) -
                        list.begin());
  c.counts = {uint32_t(list.size()), camera.frame_index, camera.cut, dropped};
  c.light_groups = {first[1], first[2], first[3], 0};

  auto& constants = ctx.output("frame.constants");
  constants.resize(sizeof(c));
  std::memcpy(constants.data(), &c, sizeof(c));
  auto& views = ctx.output("frame.views");
  views.resize(sizeof(camera_view));
  std::memcpy(views.data(), &camera_view, sizeof(camera_view));
  auto& light_bytes = ctx.output("frame.lights");
  light_bytes.resize(list.size() * sizeof(GpuLight));
  if (!list.empty()) std::memcpy(light_bytes.data(), list.data(), light_bytes.size());
}

}  // namespace

GpuLight relative_light(const LightRecord& l, uint32_t index, const glm::dvec3& eye) {
  GpuLight g{};
  const glm::dvec3 start = glm::dvec3(l.position[0], l.position[1], l.position[2]) - eye;
  const glm::dvec3 end = glm::dvec3(l.end[0], l.end[1], l.end[2]) - eye;
  const glm::vec3 direction = glm::normalize(glm::vec3(l.direction[0], l.direction[1], l.direction[2]));
  g.position_type = glm::vec4(glm::vec3(start), float(l.type));
  g.end_radius = glm::vec4(glm::vec3(end), l.radius);
  g.color_range = glm::vec4(glm::vec3(l.color[0], l.color[1], l.color[2]) * l.intensity, l.range);
  g.direction_cos_outer = glm::vec4(direction, std::cos(l.outer_cone));
  g.cos_inner = glm::vec4(std::cos(l.inner_cone), float(index), 0, 0);
  return g;
}

PassDecl frame_constants_pass() {
  return PassDecl("frame.constants", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("scene.lights", Use::host)
      .read("cull.occlusion", Use::host)
      .write("frame.constants", Use::host, BufferDecl{kinds::buffer})
      .write("frame.views", Use::host, BufferDecl{kinds::buffer})
      .write("frame.lights", Use::host, BufferDecl{kinds::buffer})
      .layout("frame.constants", frame_constants_schema())
      .layout("frame.views", view_schema())
      .layout("frame.lights", light_schema())
      .param(taa_enabled_param())
      .param_int("supersample", 0, 0, 64,
                 "n > 0: frame k's projection is offset to sample k mod n² of an n×n multi-jittered pattern over "
                 "the pixel in place of TAA's jitter; n² still frames rendered so with taa.enabled=0 and averaged "
                 "supersample the frame")
      .run(build_constants);
}

}  // namespace nightcap
