// Light leaking through a wall in the GI volume: two roofed rooms side by side, 0.4 m of wall
// between them (its middle on a cell boundary, as the grid's metres-per-cell make it at x = 0),
// the west room lit by a glowing floor, the east one by nothing but the ambient term, a probe
// in each whose box is its room. The leak: what the glow adds to the volume's mean irradiance
// (band 0) along a line across the wall (the volume with the floor glowing less the volume with
// it dark), relative to the lit room's at its middle:
// - on the dark side, from the first cell centre past the wall on (x ≥ 1 m with 2 m cells),
//   none: its cells gather its probe alone (≤ 10⁻³, measured 0);
// - between the two cell centres either side of the wall the trilinear weights mix the rooms:
//   at the dark side's wall face (0.2 m from the wall's middle) 40% of the lit side's nearest cell
//   is read, ≤ 25% of the lit room's middle (measured 18%: that cell holds 46% of the middle,
//   its probe's weight fading toward the wall).
// The cell's size sets that floor: a leak reaches at most one cell past a wall.
#include <cmath>

#include "passes/assembly/renderer.h"
#include "passes/gi/volume_layout.h"
#include "passes/scene/scene_kit.h"
#include "tests/reference/gi_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

Scene two_rooms(float glow_strength) {
  Scene scene;
  scene.source = "two rooms and a wall";
  scene_kit::Builder build(scene);
  const uint32_t grey = build.material(scene_kit::plain("wall", {0.6f, 0.6f, 0.6f}, 0.0f, 0.8f, stencil::plain));
  Material glow = scene_kit::plain("glowing floor", {0.8f, 0.8f, 0.8f}, 0.0f, 0.8f, stencil::plain);
  glow.emissive = glm::vec3(1.0f, 0.9f, 0.8f);
  glow.emissive_strength = glow_strength;
  const uint32_t glowing = build.material(glow);
  auto place = [&](const dvec3& centre, const dvec3& half, uint32_t material) {
    build.place(build.box(glm::vec3(half), material, 1.0f, true, true), centre);
  };
  place({0.0, -0.5, 0.0}, {30.0, 0.5, 30.0}, grey);     // the ground
  place({-5.0, 0.05, 0.0}, {4.0, 0.05, 4.0}, glowing);  // the west room's floor
  place({0.0, 2.5, 0.0}, {0.2, 2.5, 6.0}, grey);        // the wall between the rooms
  place({-10.2, 2.5, 0.0}, {0.2, 2.5, 6.4}, grey);
  place({10.2, 2.5, 0.0}, {0.2, 2.5, 6.4}, grey);
  place({0.0, 2.5, -6.2}, {10.4, 2.5, 0.2}, grey);
  place({0.0, 2.5, 6.2}, {10.4, 2.5, 0.2}, grey);
  place({0.0, 5.2, 0.0}, {10.4, 0.2, 6.4}, grey);  // the roof
  scene.probes.push_back({{-5.0, 2.5, 0.0}, {-10.0, 0.0, -6.0}, {-0.2, 5.0, 6.0}});
  scene.probes.push_back({{5.0, 2.5, 0.0}, {0.2, 0.0, -6.0}, {10.0, 5.0, 6.0}});
  scene.lights.push_back(scene_kit::moon());
  Camera camera;
  camera.yfov = glm::radians(70.0f);
  camera.znear = 0.05f;
  camera.world = glm::inverse(glm::lookAt(dvec3(6.0, 2.0, 3.0), dvec3(0.0, 2.0, 0.0), dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  return scene;
}

class GiLeak : public GpuTest {};

TEST_F(GiLeak, ALeakReachesNoFurtherThanACellPastTheWall) {
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.motion = CameraPath::Motion::still;
  // The volume with the floor glowing and dark: what differs on the dark side is what leaked.
  struct Volume {
    GpuGiVolume record;
    std::vector<uint8_t> cells;
    dvec3 eye;
  };
  auto render = [&](float glow) {
    const Scene scene = two_rooms(glow);
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    EXPECT_TRUE(first_non_finite(frame.execution).empty()) << first_non_finite(frame.execution);
    return Volume{host_records<GpuGiVolume>(*frame.execution.final_version("gi.volume_data")->bytes).at(0),
                  *frame.execution.final_version("gi.volume")->bytes, dvec3(frame.camera.world[3])};
  };
  const Volume glowing = render(20.0f), dark = render(0.0f);
  ASSERT_EQ(glowing.record.origin.w, 2.0f) << "the wall's middle on a cell boundary";
  // The mean irradiance at world (x, 2.5, 1): 2.5 m up and 1 m along z are cells' middles,
  // away from their boundaries along y and z.
  auto mean_at = [](const Volume& v, double x) {
    return reference::gi_lookup(v.record, v.cells, dvec3(x, 2.5, 1.0) - v.eye, dvec3(0, 1, 0), 2).band0;
  };
  const double lit = mean_at(glowing, -5.0);
  ASSERT_GT(lit, 50.0 * mean_at(glowing, 5.0)) << "the glowing floor lights the west room";
  std::printf(
      "two rooms: the lit room's mean irradiance %.4g at its middle; what the glow adds across the wall, "
      "of that:\n",
      lit);
  double beyond_a_cell = 0.0;
  for (const double x : {-1.0, -0.2, 0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0}) {
    const double leak = (mean_at(glowing, x) - mean_at(dark, x)) / lit;
    std::printf("  x = %+.1f m: %.4f\n", x, leak);
    if (x >= 1.0) beyond_a_cell = std::max(beyond_a_cell, std::abs(leak));
  }
  const double leak_at_face = (mean_at(glowing, 0.2) - mean_at(dark, 0.2)) / lit;
  EXPECT_LE(beyond_a_cell, 1e-3);
  EXPECT_LE(leak_at_face, 0.25);
  EXPECT_GT(leak_at_face, 0.0) << "the trilinear weights mix the rooms within a cell of the wall";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
