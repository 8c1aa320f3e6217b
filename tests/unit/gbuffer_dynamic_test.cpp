// gbuffer.dynamic against analytically reprojected positions. A street of static boxes, with
// cars and a walker moving at known velocities, seen by a walking camera; frame 3 is checked.
// Every pixel's surface point P comes from depth.linear and the pixel centre (double precision);
// its previous position is P − v·Δt for a pixel of a moving instance (v its velocity) and P for
// a static one; that point projected by the previous camera (a pinhole built here from the
// camera's basis, not from camera_math.h) gives the previous uv, and the motion target must hold
// uv(current) − uv(previous).
//
// Bound: |GPU − reference| ≤ 2⁻¹¹·|reference| + 2⁻¹⁸ per component: half-float storage (half an
// ULP, 2⁻¹¹ relative) plus the float error of the interpolated previous position and of the
// depth the reference starts from (both below 10⁻⁶ in uv at these distances).
//
// Stencil: pixels of moving instances hold their class with the moving flag (0x02) OR-ed on,
// static pixels never have it.
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "passes/assembly/renderer.h"
#include "passes/frame/gpu_types.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// uv ([0, 1], y down) of a world point seen by a pinhole camera.
glm::dvec2 project(const Camera& camera, double aspect, const glm::dvec3& world) {
  const glm::dmat3 basis(camera.world);
  const glm::dvec3 local = glm::transpose(basis) * (world - glm::dvec3(camera.world[3]));
  const double t = std::tan(double(camera.yfov) / 2);
  const double x = local.x / (-local.z) / (t * aspect), y = local.y / (-local.z) / t;
  return {0.5 * x + 0.5, 0.5 - 0.5 * y};
}

class GBufferDynamic : public GpuTest {};

TEST_F(GBufferDynamic, MotionVectorsMatchAnalyticReprojection) {
  Scene scene = build_city(4);
  // Some instances start to move: every car part one way, a share of the buildings (shells and
  // roofs, plain class) another.

  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Material& m = scene.materials[scene.material_of(scene.instances[i])];
    glm::vec3 v(0.0f);
    if (m.stencil_class == stencil::vehicle) v = {9.0f, 0.0f, -4.0f};
    if ((m.name == "roof" || m.name.rfind("facade", 0) == 0) && i % 3 == 0) v = {4.0f, 3.0f, -2.0f};
    if (v == glm::vec3(0.0f)) continue;
    scene.instances[i].moving = true;
    scene.instances[i].velocity = v;
  }
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.path.motion = CameraPath::Motion::walk;
  Renderer renderer(*gpu_, scene, settings);
  for (uint32_t k = 0; k < 3; ++k) renderer.render_frame(k, false);
  const RenderedFrame frame = renderer.render_frame(3, true);
  const Camera previous = frame_camera(base_camera(scene, settings), scene, settings.path, 2);
  const auto& motion = *frame.execution.final_version("gbuffer.motion")->bytes;
  const auto& depth = *frame.execution.final_version("depth.linear")->bytes;
  const auto& stencil_depth = *frame.execution.final_version("scene.depth")->bytes;
  const auto& draws = *frame.execution.final_version("draws.gbuffer.dynamic")->bytes;
  ASSERT_GT(draws.size(), 0u) << "no moving instance in view";

  // Frame 3 is jittered: pixel (x, y) shows what lies at (x + 0.5, y + 0.5) − jitter, and its
  // motion vector is that position's, unjittered.
  const glm::vec4 jitter = host_records<GpuView>(*frame.execution.final_version("frame.views")->bytes).at(0).jitter;
  ASSERT_NE(glm::vec2(jitter), glm::vec2(0.0f));
  const double aspect = double(settings.width) / settings.height;
  const double t = std::tan(double(frame.camera.yfov) / 2);
  const glm::dvec3 eye(frame.camera.world[3]);
  const glm::dmat3 basis(frame.camera.world);
  const size_t texels = size_t(settings.width) * settings.height;
  size_t moving_pixels = 0, static_pixels = 0;
  double worst = 0;
  for (uint32_t y = 0; y < settings.height; ++y)
    for (uint32_t x = 0; x < settings.width; ++x) {
      const size_t i = size_t(y) * settings.width + x;
      float d;
      std::memcpy(&d, depth.data() + 4 * i, 4);
      if (!(d < 1e5f)) continue;
      const uint8_t stencil = stencil_depth[4 * texels + i];
      const bool moving = (stencil & stencil::moving) != 0;
      const double px = x + 0.5 - jitter.x, py = y + 0.5 - jitter.y;
      const double u = (2.0 * px / settings.width - 1.0) * t * aspect;
      const double w = (1.0 - 2.0 * py / settings.height) * t;
      const glm::dvec3 p = eye + basis * glm::dvec3(u * d, w * d, -double(d));
      glm::dvec3 before = p;
      if (moving) {
        // Which moving instance: the only classes that move here are vehicles and buildings.
        EXPECT_TRUE(stencil == (stencil::vehicle | stencil::moving) || stencil == stencil::moving)
            << "stencil " << int(stencil) << " at " << x << "," << y;
        const glm::vec3 v = stencil == (stencil::vehicle | stencil::moving) ? glm::vec3(9.0f, 0.0f, -4.0f)
                                                                            : glm::vec3(4.0f, 3.0f, -2.0f);
        before -= glm::dvec3(v) * kFrameSeconds;
        ++moving_pixels;
      } else {
        ++static_pixels;
      }
      const glm::dvec2 expected =
          glm::dvec2(px / settings.width, py / settings.height) - project(previous, aspect, before);
      uint16_t h[2];
      std::memcpy(h, motion.data() + 4 * i, 4);
      for (int c = 0; c < 2; ++c) {
        const double got = half_to_float(h[c]);
        const double bound = std::ldexp(std::abs(expected[c]), -11) + std::ldexp(1.0, -18);
        worst = std::max(worst, std::abs(got - expected[c]) / bound);
        ASSERT_LE(std::abs(got - expected[c]), bound)
            << (moving ? "moving" : "static") << " pixel " << x << "," << y << " component " << c;
      }
    }
  EXPECT_GT(moving_pixels, 200u);
  EXPECT_GT(static_pixels, 200u);
  std::printf("gbuffer.dynamic: %zu moving and %zu static pixels, worst error %.3f of the bound\n", moving_pixels,
              static_pixels, worst);
}

// Moving instances in the scene but none in view: cull.main leaves draws.gbuffer.dynamic empty
// and the executor skips the pass with that reason; the G-buffer is the static one.
TEST_F(GBufferDynamic, SkippedWhenNoMovingInstanceIsVisible) {
  Scene scene = build_city(4);
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.motion = CameraPath::Motion::still;
  Renderer still(*gpu_, scene, settings);
  const RenderedFrame reference = still.render_frame(0, true);
  // A car far behind the camera, driving away from it.
  Instance car = scene.instances.front();
  const Camera camera = base_camera(scene, settings);
  car.world = glm::translate(glm::dmat4(1.0), glm::dvec3(camera.world[3]) + 500.0 * glm::dvec3(camera.world[2]));
  car.moving = true;
  car.velocity = glm::vec3(glm::dvec3(camera.world[2]) * 10.0);
  scene.instances.push_back(car);
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  bool found = false;
  for (const CompiledPass& pass : frame.graph.passes)
    if (pass.decl->name == "gbuffer.dynamic") {
      found = true;
      EXPECT_FALSE(pass.runs);
      EXPECT_EQ(pass.reason, "inputs all cleared (draws.gbuffer.dynamic)");
    }
  EXPECT_TRUE(found);
  for (const char* target : {"gbuffer.albedo", "gbuffer.normal", "gbuffer.motion", "scene.depth"})
    EXPECT_EQ(*frame.execution.final_version(target)->bytes, *reference.execution.final_version(target)->bytes)
        << target;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
