// The GI volume under stress: the camera 8 km up (the volume far above the scene, out of every
// probe's reach), at the map's far corner, a cut (the volume refills), the probe nearest the
// camera missing and the sky switched off (nothing to gather). Each renders into a capture whose float outputs stay
// finite and whose GI and probe-irradiance passes replay from their records bit for bit, every frame
// (verified_capture.h).
#include <algorithm>

#include "passes/assembly/renderer.h"
#include "passes/gi/volume_layout.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/moved_scene.h"
#include "tests/unit/scratch_folder.h"
#include "tests/unit/verified_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

const std::vector<std::string> kGiPasses = {"probes.irradiance", "gi.plan", "gi.volume"};

class GiStress : public GpuTest {
 protected:
  // Each frame's gi.plan record, from a checked capture of `frames` frames.
  std::vector<GiPlan> render_and_verify(const Scene& scene, RenderSettings settings, uint32_t frames) {
    ScratchFolder folder("gi-stress");
    settings.width = 160;
    settings.height = 90;
    const Capture capture = render_verified(*gpu_, scene, settings, frames, kGiPasses, folder.path / "cap");
    std::vector<GiPlan> plans;
    for (uint32_t f = 0; f < frames; ++f)
      for (const GiPlan& plan : recorded<GiPlan>(capture, f, "gi.plan", "gi.plan")) plans.push_back(plan);
    return plans;
  }
};

TEST_F(GiStress, EightKilometresUp) {
  Scene scene = build_map({1, 16.0, Shot::street});
  scene.camera->world[3].y += 8000.0;
  const std::vector<GiPlan> plans = render_and_verify(scene, {}, 2);
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_GT(plans[0].origin_cell[1], 3000) << "the volume lies far above the scene";
}

TEST_F(GiStress, AtTheMapsFarCorner) {
  const Scene scene = moved(build_map({1, 1.0, Shot::street}), {7500.0, 0.0, 7500.0});
  const std::vector<GiPlan> plans = render_and_verify(scene, {}, 2);
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_EQ(plans[0].refresh, uint32_t(GiRefresh::no_history));
}

TEST_F(GiStress, ACutRefillsTheVolume) {
  RenderSettings settings;
  settings.path.cuts = {2};
  const std::vector<GiPlan> plans = render_and_verify(build_map({1, 16.0, Shot::street}), settings, 3);
  ASSERT_EQ(plans.size(), 3u);
  EXPECT_EQ(plans[0].refresh, uint32_t(GiRefresh::no_history));
  EXPECT_EQ(plans[1].refresh, uint32_t(GiRefresh::kept));
  EXPECT_EQ(plans[2].refresh, uint32_t(GiRefresh::no_history)) << "a cut empties the volume's history";
  EXPECT_EQ(plans[2].refreshed_cells, plans[2].cells * plans[2].cells * plans[2].cells);
}

TEST_F(GiStress, TheNearestProbeMissing) {
  Scene scene = build_map({1, 16.0, Shot::street});
  const glm::dvec3 eye(scene.camera->world[3]);
  ASSERT_FALSE(scene.probes.empty());
  const auto nearest = std::min_element(scene.probes.begin(), scene.probes.end(), [&](const auto& a, const auto& b) {
    return glm::length(a.position - eye) < glm::length(b.position - eye);
  });
  scene.probes.erase(nearest);
  const std::vector<GiPlan> plans = render_and_verify(scene, {}, 2);
  ASSERT_EQ(plans.size(), 2u);
}

// The sky switched off with the sun still up: gi.plan records nothing and gi.volume clears the
// volume (nothing to gather), every frame; the composite lights without it.
TEST_F(GiStress, TheSkySwitchedOff) {
  RenderSettings settings;
  settings.params["sky"]["enabled"] = 0.0;
  const std::vector<GiPlan> plans = render_and_verify(build_map({1, 16.0, Shot::street}), settings, 2);
  EXPECT_TRUE(plans.empty());
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
