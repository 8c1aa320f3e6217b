// probes.plan against what its header promises, frame after frame with its own record as
// history: a frame without history captures every probe in range; a still camera then captures
// nothing; a walk captures at most the budget, nearest first, and every probe it meets in the
// end; a cut starts again; more probes in range than slots fill the slots with the nearest; none
// in range plans nothing. The faces' views are checked against Vulkan's cube map face selection
// (tests/reference/ibl_reference.h), independent of the plan's axes.
#include <glm/gtc/matrix_transform.hpp>

#include <random>
#include <set>

#include "passes/core/history_name.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "tests/reference/ibl_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// Probes every 10 m along +x, 3 m up, from x = 0 to 400.
Scene street_of_probes() {
  Scene scene;
  for (int k = 0; k <= 40; ++k) {
    const glm::dvec3 at(10.0 * k, 3.0, 0.0);
    scene.probes.push_back({at, at - glm::dvec3(5.0, 3.0, 8.0), at + glm::dvec3(5.0, 17.0, 8.0)});
  }
  return scene;
}

Camera camera_at(double x) {
  Camera camera;
  camera.world = glm::translate(glm::dmat4(1.0), glm::dvec3(x, 1.7, 2.0));
  return camera;
}

struct Planned {
  ProbePlan plan{};
  std::vector<GpuView> views;
  std::shared_ptr<const std::vector<uint8_t>> record;
};

class ProbesPlan : public GpuTest {
 protected:
  // Frame `index` from the camera at `x`, with `history` (the previous frame's record; none: a
  // frame without history).
  static Planned plan(const Scene& scene, double x, uint32_t index, const Planned* history, ParamValues params = {}) {
    const Imports imports = scene_imports(scene);
    std::map<std::string, IsolatedInput> inputs;
    inputs["scene.probes"] = {imports.at("scene.probes").desc, imports.at("scene.probes").bytes};
    const ImportedData camera = camera_import(camera_at(x), camera_at(x), 64, 64, index, false).at("frame.camera");
    inputs["frame.camera"] = {camera.desc, camera.bytes};
    inputs[previous("probes.plan")] =
        buffer_input(history ? std::span<const uint8_t>(*history->record) : std::span<const uint8_t>());
    const IsolatedRun run = GpuTest::run(probes_plan_pass(), inputs, 64, 64, params);
    Planned p;
    p.record = run.outputs.at("probes.plan");
    EXPECT_EQ(p.record->size(), sizeof(ProbePlan));
    std::memcpy(&p.plan, p.record->data(), sizeof(ProbePlan));
    p.views = host_records<GpuView>(*run.outputs.at("probes.views"));
    EXPECT_EQ(p.views.size(), 6u * p.plan.captured);
    return p;
  }

  static std::set<uint32_t> probes_in_slots(const ProbePlan& plan) {
    std::set<uint32_t> held;
    for (uint32_t s = 0; s < kProbeSlots; ++s)
      if (plan.slot_probe[s] != kNoProbe) held.insert(plan.slot_probe[s]);
    return held;
  }
  static uint32_t slots_in(const ProbePlan& plan, ProbeSlotState state) {
    uint32_t n = 0;
    for (uint32_t s = 0; s < kProbeSlots; ++s) n += plan.slot_state[s] == uint32_t(state);
    return n;
  }
};

TEST_F(ProbesPlan, AResetCapturesEveryProbeInRangeThenAStillCameraNone) {
  const Scene scene = street_of_probes();
  const Planned first = plan(scene, 0.0, 0, nullptr);
  EXPECT_EQ(first.plan.reset, 1u);
  // Probes at x = 0 … 140 lie within 150 m of (0, 1.7, 2).
  EXPECT_EQ(first.plan.in_range, 15u);
  EXPECT_EQ(first.plan.captured, 15u) << "a reset ignores the budget";
  EXPECT_EQ(slots_in(first.plan, ProbeSlotState::captured_reset), 15u);
  std::set<uint32_t> expected;
  for (uint32_t k = 0; k < 15; ++k) expected.insert(k);
  EXPECT_EQ(probes_in_slots(first.plan), expected);

  Planned still = first;
  for (uint32_t frame = 1; frame < 4; ++frame) {
    still = plan(scene, 0.0, frame, &still);
    EXPECT_EQ(still.plan.reset, 0u);
    EXPECT_EQ(still.plan.captured, 0u) << "frame " << frame << ": every probe is up to date";
    EXPECT_EQ(slots_in(still.plan, ProbeSlotState::up_to_date), 15u);
    for (uint32_t s = 0; s < kProbeSlots; ++s) {
      EXPECT_EQ(still.plan.slot_probe[s], first.plan.slot_probe[s]) << "a probe keeps its slot";
      if (first.plan.slot_probe[s] != kNoProbe) {
        EXPECT_EQ(still.plan.slot_captured[s], 0u) << "captured on frame 0";
      }
    }
  }
}

TEST_F(ProbesPlan, AWalkCapturesWithinTheBudgetNearestFirst) {
  const Scene scene = street_of_probes();
  Planned p = plan(scene, 0.0, 0, nullptr);
  std::set<uint32_t> captured_ever = probes_in_slots(p.plan);
  uint32_t waited = 0;
  for (uint32_t frame = 1; frame <= 30; ++frame) {
    const double x = std::min(30.0 * frame, 250.0);  // three probes a frame come in range, then it stands still
    p = plan(scene, x, frame, &p, {{"max_updates", 2.0}});
    EXPECT_LE(p.plan.captured, 2u) << "frame " << frame;
    waited += slots_in(p.plan, ProbeSlotState::waiting);
    // Captured this frame: no waiting probe is nearer than a captured one.
    double farthest_captured = -1, nearest_waiting = 1e30;
    for (uint32_t s = 0; s < kProbeSlots; ++s) {
      if (p.plan.slot_probe[s] == kNoProbe) continue;
      const double d = glm::length(scene.probes[p.plan.slot_probe[s]].position - glm::dvec3(x, 1.7, 2.0));
      EXPECT_LE(d, 150.0) << "a slot holds a probe in range only";
      if (p.plan.slot_state[s] == uint32_t(ProbeSlotState::captured_new)) {
        farthest_captured = std::max(farthest_captured, d);
        captured_ever.insert(p.plan.slot_probe[s]);
      }
      if (p.plan.slot_state[s] == uint32_t(ProbeSlotState::waiting)) nearest_waiting = std::min(nearest_waiting, d);
    }
    EXPECT_LE(farthest_captured, nearest_waiting) << "frame " << frame;
  }
  EXPECT_GT(waited, 0u) << "the walk should outrun the budget somewhere";
  EXPECT_EQ(slots_in(p.plan, ProbeSlotState::waiting), 0u) << "standing still, the budget catches up";
  for (uint32_t probe : probes_in_slots(p.plan)) EXPECT_TRUE(captured_ever.count(probe)) << probe;

  // A cut (no history): everything in range again, at once.
  const Planned cut = plan(scene, 250.0, 31, nullptr, {{"max_updates", 2.0}});
  EXPECT_EQ(cut.plan.reset, 1u);
  EXPECT_EQ(cut.plan.captured, cut.plan.in_range);
}

TEST_F(ProbesPlan, StaleCapturesAreTakenAgainOldestFirst) {
  const Scene scene = street_of_probes();
  Planned p = plan(scene, 0.0, 0, nullptr);
  ParamValues params{{"max_updates", 4.0}, {"refresh_frames", 10.0}};
  for (uint32_t frame = 1; frame < 10; ++frame) {
    p = plan(scene, 0.0, frame, &p, params);
    EXPECT_EQ(p.plan.captured, 0u);
  }
  uint32_t total = 0;
  for (uint32_t frame = 10; frame < 14; ++frame) {
    p = plan(scene, 0.0, frame, &p, params);
    EXPECT_EQ(p.plan.captured, std::min(4u, 15u - total)) << "frame " << frame;
    EXPECT_EQ(slots_in(p.plan, ProbeSlotState::captured_stale), p.plan.captured);
    total += p.plan.captured;
  }
  EXPECT_EQ(total, 15u) << "every capture refreshed once";
}

TEST_F(ProbesPlan, MoreProbesThanSlotsKeepTheNearestAndNoneInRangePlansNothing) {
  const Scene scene = street_of_probes();
  const Planned wide = plan(scene, 200.0, 0, nullptr, {{"range_metres", 1000.0}});
  EXPECT_EQ(wide.plan.in_range, 41u);
  EXPECT_EQ(wide.plan.captured, kProbeSlots);
  std::set<uint32_t> nearest;  // probes 4 … 35 are the 32 nearest to x = 200
  for (uint32_t k = 4; k < 36; ++k) nearest.insert(k);
  EXPECT_EQ(probes_in_slots(wide.plan), nearest);

  const Planned none = plan(scene, 5000.0, 0, nullptr);
  EXPECT_EQ(none.plan.in_range, 0u);
  EXPECT_EQ(none.plan.captured, 0u);
  EXPECT_EQ(probes_in_slots(none.plan), std::set<uint32_t>{});
  const Planned empty = plan(Scene{}, 0.0, 0, nullptr);
  EXPECT_EQ(empty.plan.in_range, 0u);
}

// Each face's view puts a direction where Vulkan's cube map face selection says it is seen:
// a point one metre from the probe along a random direction projects, through the view of the
// face the direction selects, to that face's (s, t), and in front of its near plane.
TEST_F(ProbesPlan, FaceViewsAreTheCubeMapsFaces) {
  const Scene scene = street_of_probes();
  const Planned p = plan(scene, 33.0, 0, nullptr);
  ASSERT_GE(p.plan.captured, 1u);
  const glm::dvec3 camera(33.0, 1.7, 2.0);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  double worst = 0;
  for (uint32_t k = 0; k < p.plan.captured; ++k) {
    const glm::dvec3 probe = scene.probes[p.plan.slot_probe[p.plan.capture_slot[k]]].position;
    for (int sample = 0; sample < 200; ++sample) {
      const glm::dvec3 d = glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
      uint32_t face;
      double s, t;
      reference::face_coordinates(d, face, s, t);
      const GpuView& view = p.views[6 * k + face];
      EXPECT_EQ(view.viewport, glm::vec4(64, 64, 1.0f / 64, 1.0f / 64)) << "face_size";
      EXPECT_LT(glm::length(glm::dvec3(glm::vec3(view.eye)) - (probe - camera)), 1e-5);
      const glm::dvec4 clip = glm::dmat4(view.view_projection) * glm::dvec4(probe - camera + d, 1.0);
      ASSERT_GT(clip.w, 0.0);
      const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
      // The view sees the face as a camera does: its x runs against the cube's s.
      worst = std::max({worst, std::abs(-ndc.x - (2 * s - 1)), std::abs(ndc.y - (2 * t - 1))});
      EXPECT_GT(clip.z / clip.w, 0.0);
      EXPECT_LT(clip.z / clip.w, 1.0);
    }
  }
  EXPECT_LT(worst, 1e-5);
  std::printf("face views: worst NDC error %.2g\n", worst);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
