// Stress cases for the geometry passes (cull.main, depth.prepass, gbuffer.opaque) and what
// reads them: degenerate and extreme geometry renders without NaN or Inf in any output.
#include <cmath>
#include <cstring>

#include "passes/assembly/renderer.h"
#include "passes/frame/gpu_types.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// One triangle per instance, each a different kind of trouble.
Scene hostile_scene() {
  Scene scene;
  scene.source = "stress";
  Material m;
  m.name = "grey";
  m.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  m.roughness = 0.0f;  // zero roughness: the lighting floor must keep highlights finite
  m.metallic = 0.0f;
  scene.materials.push_back(m);
  auto triangle = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 normal, glm::dmat4 world) {
    Primitive p;
    p.first_index = uint32_t(scene.indices.size());
    p.vertex_offset = int32_t(scene.vertices.size());
    p.index_count = 3;
    p.bounds_min = glm::min(a, glm::min(b, c));
    p.bounds_max = glm::max(a, glm::max(b, c));
    for (const glm::vec3& corner : {a, b, c}) {
      Vertex v{};
      std::memcpy(v.position, &corner[0], 12);
      std::memcpy(v.normal, &normal[0], 12);
      for (float& x : v.color) x = 1.0f;
      scene.vertices.push_back(v);
    }
    for (uint32_t i = 0; i < 3; ++i) scene.indices.push_back(i);
    scene.primitives.push_back(p);
    scene.instances.push_back({world, uint32_t(scene.primitives.size() - 1), false});
  };
  const glm::vec3 up(0, 1, 0);
  triangle({-50, 0, -50}, {0, 0, 50}, {50, 0, -50}, up, glm::dmat4(1.0));             // ground
  triangle({1, 1, 1}, {1, 1, 1}, {1, 1, 1}, up, glm::dmat4(1.0));                     // a point
  triangle({0, 1, 0}, {1, 2, 0}, {2, 3, 0}, {0, 0, 1}, glm::dmat4(1.0));              // collinear
  triangle({-1e5f, 2, -1e5f}, {0, 2, 1e5f}, {1e5f, 2, -1e5f}, -up, glm::dmat4(1.0));  // 100 km wide
  triangle({0, 0, 0}, {1e-6f, 0, 0}, {0, 1e-6f, 0}, {0, 0, 1}, glm::dmat4(1.0));      // a micrometre
  triangle({-1, 0, -1}, {0, 0, 1}, {1, 0, -1}, up, glm::dmat4(0.0));                  // zero scale
  triangle({-5, 0.5, 10}, {0, 3, -10}, {5, 0.5, 10}, {0, 0, 1}, glm::dmat4(1.0));     // through the near plane
  triangle({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 0}, glm::dmat4(1.0));              // zero normal
  Light touching;  // a light on the ground: distance → 0
  touching.type = LightType::point;
  touching.position = glm::dvec3(0.0, 0.0, 0.0);
  touching.intensity = 100.0f;
  scene.lights.push_back(touching);
  Light tube;
  tube.type = LightType::tube;
  tube.position = glm::dvec3(-1.0, 1e-4, 2.0);
  tube.end = glm::dvec3(1.0, 1e-4, 2.0);  // lying on the ground
  tube.intensity = 50.0f;
  scene.lights.push_back(tube);
  scene.camera = orbit_camera(20.0, 70.0, 12.0, {0.0, 0.0, 0.0}, 60.0);
  return scene;
}

class GeometryStress : public GpuTest {};

TEST_F(GeometryStress, DegenerateAndExtremeGeometryStaysFinite) {
  const Scene scene = hostile_scene();
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  ASSERT_EQ(first_non_finite(frame.execution), "");
  // The zero-scale instance was dropped by cull.main rather than drawn with a singular matrix.
  const VersionData* draws = frame.execution.final_version("draws.gbuffer.opaque");
  ASSERT_NE(draws, nullptr);
  EXPECT_EQ(draws->bytes->size() / sizeof(GpuDraw), scene.instances.size() - 1);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// glTF: a transform with a negative determinant flips the winding; the near face of a mirrored
// cube must still be the one drawn, with its normal toward the camera.
TEST_F(GeometryStress, MirroredTransformsKeepTheirFrontFaces) {
  Scene scene = load_gltf(std::string(NIGHTCAP_SHARED_DATA) + "/gltf/BoxTextured/glTF/BoxTextured.gltf");
  for (Instance& instance : scene.instances)
    instance.world =
        glm::dmat4(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, 0, 0, 1)) *
        instance.world;
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = settings.height = 64;
  settings.camera = orbit_camera(0.0, 90.0, 3.0, {0.0, 0.0, 0.0}, 45.0);
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  const size_t centre = 32 * 64 + 32;
  float depth;
  std::memcpy(&depth, frame.execution.final_version("scene.depth")->bytes->data() + 4 * centre, 4);
  EXPECT_NEAR(settings.camera->znear / depth, 2.5, 1e-3);  // the near face, 2.5 from the camera
  uint32_t word;
  std::memcpy(&word, frame.execution.final_version("gbuffer.normal")->bytes->data() + 4 * centre, 4);
  EXPECT_GT(((word >> 20) & 1023) / 1023.0 * 2.0 - 1.0, 0.9);  // facing the camera (+Z)
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
