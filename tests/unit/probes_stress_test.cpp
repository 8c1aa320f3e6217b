// The reflection probes under stress: a probe inside a building, probes at the map's far corner,
// a camera cut, no probe in range and more than 32 in range. Each renders into a capture whose
// every float output stays finite, and whose probe passes replay from their records bit for bit
// (`replay --verify`), every frame.
#include <cmath>
#include <cstring>

#include "passes/assembly/renderer.h"
#include "passes/probes/plan.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/moved_scene.h"
#include "tests/unit/scratch_folder.h"
#include "tests/unit/verified_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

const std::vector<std::string> kProbePasses = {"probes.plan", "probes.cull",    "probes.gbuffer",   "probes.light",
                                               "probes.keep", "probes.convert", "probes.irradiance"};

class ProbesStress : public GpuTest {
 protected:
  // Renders `frames` of `scene` into a checked capture (verified_capture.h) and returns each
  // frame's plan.
  std::vector<ProbePlan> render_and_verify(const Scene& scene, RenderSettings settings, uint32_t frames) {
    ScratchFolder folder("probes-stress");
    const Capture capture = render_verified(*gpu_, scene, settings, frames, kProbePasses, folder.path / "cap");
    std::vector<ProbePlan> plans;
    for (uint32_t f = 0; f < frames; ++f)
      for (const ProbePlan& plan : recorded<ProbePlan>(capture, f, "probes.plan", "probes.plan")) plans.push_back(plan);
    return plans;
  }

  static RenderSettings small() {
    RenderSettings settings;
    settings.width = 160;
    settings.height = 90;
    return settings;
  }
};

TEST_F(ProbesStress, AProbeInsideABuildingStaysFinite) {
  Scene scene = build_city(1);
  ASSERT_EQ(scene.probes.size(), 1u);
  // The middle of the tallest instance's box: inside a building, every face sees its walls from
  // within (back faces, culled: the faces see through them to the street).
  double tallest = 0;
  glm::dvec3 inside(0.0);
  for (const Instance& instance : scene.instances) {
    const Primitive& p = scene.primitives.at(instance.primitive);
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner(k & 1 ? p.bounds_max.x : p.bounds_min.x, k & 2 ? p.bounds_max.y : p.bounds_min.y,
                              k & 4 ? p.bounds_max.z : p.bounds_min.z);
      const glm::dvec3 world(instance.world * glm::dvec4(corner, 1.0));
      lo = glm::min(lo, world);
      hi = glm::max(hi, world);
    }
    if (hi.y - lo.y > tallest) {
      tallest = hi.y - lo.y;
      inside = 0.5 * (lo + hi);
    }
  }
  ASSERT_GT(tallest, 10.0);
  scene.probes[0].position = inside;
  const std::vector<ProbePlan> plans = render_and_verify(scene, small(), 2);
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_EQ(plans[0].captured, 1u);
}

// The map's far corner, 10.6 km out: the faces' G-buffer is the one captured at the origin, bit
// for bit (camera-relative views, tests/unit/far_origin_test.cpp), and their light within 10⁻³
// RMS of the origin's, relative to its RMS: the sun's shadow maps are snapped to world-space
// texels (so that they do not shimmer as the camera moves), so a few shadow edges fall elsewhere
// (2.8 × 10⁻⁴ measured; the frame's own lighting.lit differs by 6 × 10⁻⁵).
TEST_F(ProbesStress, AtTheMapsFarCornerTheCapturesAreTheOriginsUpToShadowSnapping) {
  const Scene near = build_map({1, 1.0, Shot::street});
  const Scene far = moved(near, {7500.0, 0.0, 7500.0});
  const std::vector<ProbePlan> plans = render_and_verify(far, small(), 2);
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_GT(plans[0].captured, 0u);

  Renderer near_renderer(*gpu_, near, small()), far_renderer(*gpu_, far, small());
  const RenderedFrame a = near_renderer.render_frame(0, true), b = far_renderer.render_frame(0, true);
  for (const char* name : {"probes.gbuffer.albedo", "probes.gbuffer.normal", "probes.gbuffer.material",
                           "probes.gbuffer.emissive", "probes.depth"})
    EXPECT_EQ(*a.execution.final_version(name)->bytes, *b.execution.final_version(name)->bytes) << name;
  for (const char* name : {"probes.faces", "probes.array"}) {
    const std::vector<uint8_t>&at_origin = *a.execution.final_version(name)->bytes,
          &at_corner = *b.execution.final_version(name)->bytes;
    ASSERT_EQ(at_origin.size(), at_corner.size()) << name;
    double squares = 0, signal = 0;
    for (size_t i = 0; i + 2 <= at_origin.size(); i += 2) {
      uint16_t x, y;
      std::memcpy(&x, at_origin.data() + i, 2);
      std::memcpy(&y, at_corner.data() + i, 2);
      const double origin = half_to_float(x), corner = half_to_float(y);
      squares += (corner - origin) * (corner - origin);
      signal += origin * origin;
    }
    EXPECT_GT(signal, 0.0) << name;
    std::printf("%s at the far corner: %.3g RMS of the origin's, relative\n", name, std::sqrt(squares / signal));
    EXPECT_LE(std::sqrt(squares / signal), 1e-3) << name;
  }
}

TEST_F(ProbesStress, ACutCapturesEveryProbeInRangeAgain) {
  RenderSettings settings = small();
  settings.path.cuts = {2};
  const std::vector<ProbePlan> plans = render_and_verify(build_city(1), settings, 3);
  ASSERT_EQ(plans.size(), 3u);
  EXPECT_EQ(plans[0].reset, 1u);
  EXPECT_EQ(plans[1].reset, 0u);
  EXPECT_EQ(plans[1].captured, 0u) << "the probe stays captured while walking";
  EXPECT_EQ(plans[2].reset, 1u) << "a cut empties the plan's history";
  EXPECT_EQ(plans[2].captured, plans[2].in_range);
}

TEST_F(ProbesStress, MoreThanThirtyTwoInRangeFillEverySlot) {
  RenderSettings settings = small();
  settings.params["probes.plan"]["range_metres"] = 2000.0;
  const std::vector<ProbePlan> plans = render_and_verify(build_map({1, 16.0, Shot::street}), settings, 2);
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_GT(plans[0].in_range, kProbeSlots);
  EXPECT_EQ(plans[0].captured, kProbeSlots);
  EXPECT_EQ(plans[1].captured, 0u);
}

// With no probe in range the composite's reflections are the sky's: the frame is the frame with
// the probes switched off, bit for bit.
TEST_F(ProbesStress, NoProbeInRangeReflectsTheSkyAsWithProbesOff) {
  const Scene scene = build_map({1, 16.0, Shot::street});
  RenderSettings none = small(), off = small();
  none.params["probes.plan"]["range_metres"] = 1.0;
  off.params["probes"]["enabled"] = 0.0;
  Renderer with_none(*gpu_, scene, none), without(*gpu_, scene, off);
  const RenderedFrame a = with_none.render_frame(0, true), b = without.render_frame(0, true);
  const ProbePlan plan = host_records<ProbePlan>(*a.execution.final_version("probes.plan")->bytes).at(0);
  EXPECT_EQ(plan.in_range, 0u);
  EXPECT_EQ(*a.execution.final_version("lighting.lit")->bytes, *b.execution.final_version("lighting.lit")->bytes);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
