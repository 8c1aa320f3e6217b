// Stress cases of the decal passes: the 1 km map (its lane markings, grime, graffiti, posters
// and puddles) moved to the far corner of a 16 km map, with two more projected decals — a box
// holding the camera and a box of zero size in front of it — rendered for two frames (traffic
// moving) at 1×1 and at an odd 161×91: every float output of every pass is finite, the
// camera's box is drawn and the zero-size one dropped, and each pass of the capture (the decal
// passes included) replays bit for bit from its recorded inputs alone (replay --verify).
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <set>

#include "passes/assembly/renderer.h"
#include "passes/frame/gpu_types.h"
#include "replay/replay.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/scratch_folder.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

Scene stressed_map() {
  Scene scene = build_map({1, 1.0, Shot::street});
  const glm::dvec4 offset(7500.0, 0.0, 7500.0, 0.0);
  for (Instance& instance : scene.instances) instance.world[3] += offset;
  for (Decal& decal : scene.decals) decal.world[3] += offset;
  for (Light& light : scene.lights) {
    light.position += glm::dvec3(offset);
    light.end += glm::dvec3(offset);
  }
  scene.camera->world[3] += offset;
  const glm::dvec3 eye(scene.camera->world[3]);
  Decal around_camera;
  around_camera.world = glm::scale(glm::translate(glm::dmat4(1.0), eye), glm::dvec3(6.0));
  around_camera.albedo = {0.2f, 0.9f, 0.3f};
  around_camera.opacity = 0.5f;
  around_camera.normal_weight = 1.0f;
  scene.decals.push_back(around_camera);
  Decal point;
  point.world =
      glm::scale(glm::translate(glm::dmat4(1.0), eye - glm::dvec3(scene.camera->world[2]) * 5.0), glm::dvec3(0.0));
  scene.decals.push_back(point);
  return scene;
}

class DecalsStress : public GpuTest, public ::testing::WithParamInterface<std::pair<uint32_t, uint32_t>> {};

TEST_P(DecalsStress, FiniteEverywhereAndReplaysBitIdentically) {
  const Scene scene = stressed_map();
  RenderSettings settings;
  settings.width = GetParam().first;
  settings.height = GetParam().second;
  settings.frames = 2;
  Renderer renderer(*gpu_, scene, settings);
  renderer.render_frame(0, false);
  const RenderedFrame frame = renderer.render_frame(1, true);
  ASSERT_EQ(first_non_finite(frame.execution), "");
  const auto& list = *frame.execution.final_version("draws.decals.projected")->bytes;
  bool camera_box = false;
  for (size_t k = 0; k < list.size() / sizeof(GpuDecal); ++k) {
    GpuDecal d;
    std::memcpy(&d, list.data() + k * sizeof(GpuDecal), sizeof(d));
    camera_box |= d.info.y == scene.decals.size() - 2;
    EXPECT_NE(d.info.y, scene.decals.size() - 1) << "the zero-size box was drawn";
  }
  EXPECT_TRUE(camera_box) << "the box holding the camera was dropped";

  const ScratchFolder scratch("decals-stress");
  render_to_capture(*gpu_, scene, settings, scratch.path / "capture", false);
  const Capture capture = Capture::open(scratch.path / "capture");
  for (uint32_t k : {0u, 1u}) {
    ReplayOptions options;
    options.frame = k;
    const ReplayReport report = replay_capture(*gpu_, capture, options);
    std::set<std::string> replayed;
    for (const PassReplay& pass : report.passes) {
      if (pass.replayed) replayed.insert(pass.name);
      for (const OutputCheck& out : pass.outputs)
        EXPECT_EQ(out.verdict, Verdict::identical) << "frame " << k << " " << pass.name << " " << out.resource;
    }
    for (const char* pass : {"cull.main", "decals.normal_copy", "decals.mesh", "decals.projected"})
      EXPECT_TRUE(replayed.count(pass)) << "frame " << k << ": " << pass << " not replayed";
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, DecalsStress, ::testing::Values(std::pair{1u, 1u}, std::pair{161u, 91u}),
                         [](const auto& info) {
                           return std::to_string(info.param.first) + "x" + std::to_string(info.param.second);
                         });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
