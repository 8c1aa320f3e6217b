// The built-in map (passes/scene/map.cpp) against what the geometry stage asks of it, checked on
// the scene itself and on what cull.main makes of it:
// - 16 km × 16 km with about 100 000 instances (80 000 to 130 000), meshes shared (fewer than
//   one primitive per 100 instances), building shells and roofs with three levels of detail;
// - the same scene from the same seed, another from another seed;
// - each shot where it says it is (street eye 1.7 m above the street, rooftop 60 m up, aerial
//   800 m up looking down at 45°), with at least 100 local lights within 200 m of the street
//   shot, and over 24 seeds the shots reach every quadrant more than 5 km out from the centre;
// - no shot of the full map draws more than 2 million triangles (cull.main's own count,
//   checked against the draw lists it wrote).
#include <cmath>
#include <cstring>

#include "passes/cull/cull_stats.h"
#include "passes/cull/stage.h"
#include "passes/frame/gpu_types.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

const Scene& full_map(Shot shot) {
  static std::map<Shot, Scene> maps;
  auto it = maps.find(shot);
  if (it == maps.end()) it = maps.emplace(shot, build_map({1, 16.0, shot})).first;
  return it->second;
}

glm::dvec3 eye_of(const Scene& scene) { return glm::dvec3(scene.camera->world[3]); }
glm::dvec3 forward_of(const Scene& scene) { return -glm::normalize(glm::dvec3(scene.camera->world[2])); }

TEST(Map, SpansSixteenKilometresWithAboutAHundredThousandSharedInstances) {
  const Scene& scene = full_map(Shot::street);
  const glm::dvec3 lo = scene.bounds_min(), hi = scene.bounds_max();
  EXPECT_NEAR(hi.x - lo.x, 16000.0, 50.0);
  EXPECT_NEAR(hi.z - lo.z, 16000.0, 50.0);
  EXPECT_GE(scene.instances.size(), 80000u);
  EXPECT_LE(scene.instances.size(), 130000u);
  EXPECT_LT(scene.primitives.size() * 100, scene.instances.size()) << "meshes are not shared";
  // Every building shell and roof has three levels of detail, coarser ones with fewer triangles.
  size_t buildings = 0;
  for (const Instance& instance : scene.instances) {
    const std::string& name = scene.materials[scene.material_of(instance)].name;
    if (name.rfind("facade", 0) != 0 && name != "roof") continue;
    ++buildings;
    std::vector<uint32_t> triangles;
    for (int32_t p = int32_t(instance.primitive); p >= 0; p = scene.primitives[p].coarser)
      triangles.push_back(scene.primitives[p].index_count / 3);
    ASSERT_EQ(triangles.size(), 3u) << name;
    EXPECT_GT(triangles[0], triangles[1]) << name;
    EXPECT_GT(triangles[1], triangles[2]) << name;
  }
  EXPECT_GT(buildings, 10000u);
  size_t moving = 0, foliage = 0, people = 0;
  for (const Instance& instance : scene.instances) {
    const Material& m = scene.materials[scene.material_of(instance)];
    moving += instance.moving;
    foliage += m.stencil_class == stencil::foliage;
    people += m.stencil_class == stencil::face;
    if (instance.moving) {
      EXPECT_GT(glm::length(instance.velocity), 0.5f);
    }
  }
  EXPECT_GT(moving, 1000u);
  EXPECT_GT(foliage, 100u);
  EXPECT_GT(people, 50u);
}

TEST(Map, TheSeedDecidesEverything) {
  const Scene a = build_map({7, 2.0, Shot::street}), b = build_map({7, 2.0, Shot::street});
  const Scene c = build_map({8, 2.0, Shot::street});
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) ASSERT_EQ(a.instances[i].world, b.instances[i].world);
  EXPECT_EQ(a.camera->world, b.camera->world);
  EXPECT_NE(a.instances.size() == c.instances.size() && a.camera->world == c.camera->world, true);
  const glm::dvec3 lo = a.bounds_min(), hi = a.bounds_max();
  EXPECT_NEAR(hi.x - lo.x, 2000.0, 50.0) << "--map-size 2";
  EXPECT_THROW(build_map({1, 100.0, Shot::street}), SceneError);
  EXPECT_THROW(parse_shot("helicopter"), SceneError);
}

TEST(Map, ShotsStandWhereTheySayAndReachTheFarCorners) {
  std::set<int> far_quadrants;
  for (uint32_t seed = 1; seed <= 64; ++seed)
    for (Shot shot : {Shot::street, Shot::rooftop, Shot::aerial}) {
      // The camera is chosen after the city is laid out: a small map answers for placement.
      const Scene scene = build_map({seed, shot == Shot::aerial ? 4.0 : 2.0, shot});
      const glm::dvec3 eye = eye_of(scene), forward = forward_of(scene);
      if (shot == Shot::street) {
        EXPECT_NEAR(eye.y, 1.7, 1e-9) << "seed " << seed;
        EXPECT_LT(std::abs(forward.y), 0.1);
      } else if (shot == Shot::rooftop) {
        EXPECT_NEAR(eye.y, 60.0, 1e-9) << "seed " << seed;
      } else {
        EXPECT_NEAR(eye.y, 800.0, 1e-9) << "seed " << seed;
        EXPECT_NEAR(std::asin(-forward.y), glm::radians(45.0), 1e-9);
      }
    }
  for (uint32_t seed = 1; seed <= 24; ++seed) {
    const Scene scene = build_map({seed, 16.0, Shot(seed % 3)});
    const glm::dvec3 eye = eye_of(scene);
    if (std::max(std::abs(eye.x), std::abs(eye.z)) > 5000.0) far_quadrants.insert((eye.x > 0) * 2 + (eye.z > 0));
  }
  EXPECT_EQ(far_quadrants.size(), 4u) << "shots never reach some far quadrant of the map";
}

TEST(Map, AtLeastAHundredLocalLightsWithinTwoHundredMetresOfTheStreetShot) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Scene scene = build_map({seed, 16.0, Shot::street});
    const glm::dvec3 eye = eye_of(scene);
    size_t near = 0, tubes = 0, lamps = 0;
    for (const Light& l : scene.lights) {
      if (l.type == LightType::directional) continue;
      tubes += l.type == LightType::tube;
      lamps += l.type == LightType::point;
      near += glm::length(l.position - eye) <= 200.0;
      EXPECT_GT(l.range, 0.0f) << "local lights have hand-set bounds";
    }
    EXPECT_GE(near, 100u) << "seed " << seed;
    EXPECT_GT(tubes, lamps / 2) << "most lights are neon tubes and street lamps";
  }
}

class MapCull : public GpuTest {};

TEST_F(MapCull, NoShotOfTheFullMapDrawsMoreThanTwoMillionTriangles) {
  for (Shot shot : {Shot::street, Shot::rooftop, Shot::aerial}) {
    const Scene& scene = full_map(shot);
    const Imports imports = scene_imports(scene);
    std::map<std::string, IsolatedInput> inputs;
    for (const char* name :
         {"scene.instances", "scene.meshes", "scene.hierarchy", "scene.materials", "scene.geometry", "scene.decals"})
      inputs[name] = IsolatedInput{imports.at(name).desc, imports.at(name).bytes};
    const ImportedData camera = camera_import(*scene.camera, *scene.camera, 1280, 720, 0, false).at("frame.camera");
    inputs["frame.camera"] = IsolatedInput{camera.desc, camera.bytes};
    const IsolatedRun result = run(cull_main_pass(), inputs, 1280, 720);
    CullStats stats{};
    std::memcpy(&stats, result.outputs.at("cull.stats")->data(), sizeof(stats));
    uint64_t triangles = 0;
    for (const char* list : {"draws.gbuffer.opaque", "draws.gbuffer.dynamic"}) {
      const auto& bytes = *result.outputs.at(list);
      for (size_t k = 0; k < bytes.size() / sizeof(GpuDraw); ++k) {
        GpuDraw d;
        std::memcpy(&d, bytes.data() + k * sizeof(GpuDraw), sizeof(d));
        triangles += d.index_count / 3;
      }
    }
    EXPECT_EQ(triangles, uint64_t(stats.triangles_gbuffer) + stats.triangles_dynamic);
    EXPECT_LE(triangles, 2000000u) << shot_name(shot);
    EXPECT_EQ(stats.instances_tested, scene.instances.size()) << shot_name(shot);
    EXPECT_GT(stats.visible, 100u) << shot_name(shot);
    std::printf(
        "%s: cull.main %.2f ms, %u visible of %zu, %llu triangles, %u draws, %u culled by frustum, %u by occlusion, "
        "%u by distance\n",
        shot_name(shot).c_str(), result.execution.passes.at(0).cpu_ms, stats.visible, scene.instances.size(),
        (unsigned long long)triangles, stats.draws_gbuffer + stats.draws_dynamic, stats.culled_frustum,
        stats.culled_occlusion, stats.culled_distance);
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
