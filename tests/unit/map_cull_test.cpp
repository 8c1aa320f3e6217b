// Culling never removes anything visible: on the 2 km map (4 km for the aerial shot), for the
// street, rooftop and aerial shots and from inside a building, the G-buffer (every target of
// gbuffer.opaque and gbuffer.dynamic, depth and stencil) of a frame culled by cull.main equals,
// byte for byte, that of the same frame with frustum and occlusion culling off
// (`cull.main.frustum=0`, `cull.main.occlusion=0`). Stated tolerance: none. For the shots the
// second frame is compared, so traffic and camera have moved.
//
// The lights frame.constants drops (range box outside the frustum or behind the occluders) light
// nothing visible: no pixel of the rendered depth lies within a dropped light's range. The
// pixels' positions are reconstructed from depth.linear and the camera in double precision; a
// pixel counts as within reach when it is within range + 1 cm (float depth at 2 km is good to
// about 0.2 mm).
#include <array>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <set>

#include "passes/assembly/renderer.h"
#include "passes/cull/cull_stats.h"
#include "passes/frame/gpu_types.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> final_versions(const RenderedFrame& frame) {
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> out;
  for (const char* name : {"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "gbuffer.motion", "gbuffer.emissive",
                           "scene.depth", "depth.linear", "cull.stats", "frame.lights"})
    if (const VersionData* v = frame.execution.final_version(name)) out[name] = v->bytes;
  return out;
}

// The aerial shot looks down on 4 km (a 2 km map would lie almost wholly in its view).
Scene map_for(Shot shot) { return build_map({3, shot == Shot::aerial ? 4.0 : 2.0, shot}); }

class MapCulling : public GpuTest, public ::testing::WithParamInterface<Shot> {};

TEST_P(MapCulling, CulledGBufferEqualsTheUnculledOne) {
  const Scene scene = map_for(GetParam());
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.frames = 2;
  RenderSettings unculled = settings;
  unculled.params["cull.main"] = {{"frustum", 0.0}, {"occlusion", 0.0}};
  Renderer culled_renderer(*gpu_, scene, settings), unculled_renderer(*gpu_, scene, unculled);
  culled_renderer.render_frame(0, false);
  unculled_renderer.render_frame(0, false);
  const auto a = final_versions(culled_renderer.render_frame(1, true));
  const auto b = final_versions(unculled_renderer.render_frame(1, true));
  for (const char* name :
       {"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "gbuffer.motion", "gbuffer.emissive", "scene.depth"}) {
    ASSERT_TRUE(a.count(name) && b.count(name)) << name;
    EXPECT_EQ(*a.at(name), *b.at(name)) << name << " differs when culling is off";
  }
  CullStats culled{}, all{};
  std::memcpy(&culled, a.at("cull.stats")->data(), sizeof(culled));
  std::memcpy(&all, b.at("cull.stats")->data(), sizeof(all));
  // The comparison means something: culling removed a lot, and the unculled frame drew it.
  EXPECT_GT(culled.culled_frustum, 500u);
  if (GetParam() != Shot::aerial) {
    EXPECT_GT(culled.culled_occlusion, 100u);
  }
  EXPECT_GT(all.triangles_gbuffer, culled.triangles_gbuffer);
  std::printf("%s: %u visible, %u culled by frustum, %u by occlusion; %u triangles drawn of %u unculled\n",
              shot_name(GetParam()).c_str(), culled.visible, culled.culled_frustum, culled.culled_occlusion,
              culled.triangles_gbuffer + culled.triangles_dynamic, all.triangles_gbuffer + all.triangles_dynamic);
}

TEST_P(MapCulling, DroppedLightsLightNoVisiblePixel) {
  const Scene scene = map_for(GetParam());
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  const auto v = final_versions(frame);
  // The lights kept, by camera-relative position (floats as frame.constants wrote them).
  const glm::dvec3 eye(frame.camera.world[3]);
  std::set<std::array<float, 6>> kept;
  const auto& lights = *v.at("frame.lights");
  for (size_t k = 0; k < lights.size() / sizeof(GpuLight); ++k) {
    GpuLight g;
    std::memcpy(&g, lights.data() + k * sizeof(GpuLight), sizeof(g));
    kept.insert(
        {g.position_type.x, g.position_type.y, g.position_type.z, g.end_radius.x, g.end_radius.y, g.end_radius.z});
  }
  std::vector<const Light*> dropped;
  for (const Light& l : scene.lights) {
    if (l.type == LightType::directional) continue;
    const glm::vec3 p(l.position - eye), e(l.end - eye);
    if (!kept.count({p.x, p.y, p.z, e.x, e.y, e.z})) dropped.push_back(&l);
  }
  ASSERT_GT(dropped.size(), 20u) << "the test needs dropped lights";
  // Every visible pixel's world position, from depth.linear (metres along the view axis).
  const auto& depth = *v.at("depth.linear");
  const double aspect = double(settings.width) / settings.height, ty = std::tan(double(frame.camera.yfov) / 2);
  const glm::dmat3 basis(frame.camera.world);
  std::vector<glm::dvec3> points;
  for (uint32_t y = 0; y < settings.height; ++y)
    for (uint32_t x = 0; x < settings.width; ++x) {
      float d;
      std::memcpy(&d, depth.data() + (size_t(y) * settings.width + x) * 4, 4);
      if (!(d < 1e5f)) continue;  // sky
      const double u = (2.0 * (x + 0.5) / settings.width - 1.0) * ty * aspect;
      const double w = (1.0 - 2.0 * (y + 0.5) / settings.height) * ty;
      points.push_back(eye + basis * glm::dvec3(u * d, w * d, -double(d)));
    }
  ASSERT_GT(points.size(), settings.width * settings.height / 4);
  for (const Light* l : dropped) {
    const glm::dvec3 a = l->position, b = l->type == LightType::tube ? l->end : l->position;
    for (const glm::dvec3& p : points) {
      const glm::dvec3 ab = b - a;
      const double t = glm::dot(ab, ab) > 0 ? std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
      ASSERT_GT(glm::length(p - (a + ab * t)), double(l->range) + 0.01)
          << "a dropped light reaches a visible point (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
  }
}

// Inside a building the shell's walls face away and are not drawn: the view reaches the city
// through them, so the occluders must not count them either.
class MapCullingInside : public GpuTest {};

TEST_F(MapCullingInside, CulledGBufferEqualsTheUnculledOne) {
  Scene scene = build_map({3, 2.0, Shot::street});
  uint32_t tallest = 0;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Primitive& p = scene.primitives[scene.instances[i].primitive];
    const Primitive& q = scene.primitives[scene.instances[tallest].primitive];
    if (p.bounds_max.y - p.bounds_min.y > q.bounds_max.y - q.bounds_min.y) tallest = i;
  }
  const glm::dvec3 inside = glm::dvec3(scene.instances[tallest].world[3]) + glm::dvec3(0.0, 30.0, 0.0);
  Camera camera;
  camera.world = glm::inverse(glm::lookAt(inside, inside + glm::dvec3(1.0, -0.1, 0.3), glm::dvec3(0, 1, 0)));
  camera.yfov = glm::radians(70.0f);
  camera.znear = 0.1f;
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.camera = camera;
  RenderSettings unculled = settings;
  unculled.params["cull.main"] = {{"frustum", 0.0}, {"occlusion", 0.0}};
  Renderer culled_renderer(*gpu_, scene, settings), unculled_renderer(*gpu_, scene, unculled);
  const auto a = final_versions(culled_renderer.render_frame(0, true));
  const auto b = final_versions(unculled_renderer.render_frame(0, true));
  for (const char* name : {"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "scene.depth"})
    EXPECT_EQ(*a.at(name), *b.at(name)) << name << " differs when culling is off";
  CullStats culled{};
  std::memcpy(&culled, a.at("cull.stats")->data(), sizeof(culled));
  EXPECT_GT(culled.culled_frustum, 100u);
}

INSTANTIATE_TEST_SUITE_P(Shots, MapCulling, ::testing::Values(Shot::street, Shot::rooftop, Shot::aerial),
                         [](const auto& info) { return shot_name(info.param); });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
