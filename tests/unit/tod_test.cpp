// Time of day (passes/scene/time_of_day.h): the sun and moon for an hour against values worked
// by hand, the bake's determinism, the table file's checks, and the filter in shadow.cull
// against the unfiltered shadow. Bounds (issue 14, accuracy.md): of the pixels shadowed with or
// without the filter, shadow.sun agrees at ≥ 99.9% at a baked hour and at ≥ 99% between two.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "passes/assembly/renderer.h"
#include "passes/frame/gpu_types.h"
#include "passes/scene/scene_kit.h"
#include "passes/scene/time_of_day.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/stage.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/recorded_pass.h"
#include "tests/unit/scratch_folder.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

void expect_near(const dvec3& a, const dvec3& b, double tolerance, const char* what) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tolerance) << what << ", component " << k;
}

// sin and cos of 37.8° and 45°, to 5 digits from a table: 0.61291, 0.79016, 0.70711.
TEST(TimeOfDay, SunAndMoonMatchHandComputedPositions) {
  // Noon: due south (+z), 90° − 37.8° = 52.2° up.
  expect_near(sun_towards(12.0), {0.0, 0.79016, 0.61291}, 1e-5, "noon");
  // 9:00, hour angle −45°: east of south; (sin 45°, cos φ cos 45°, sin φ cos 45°).
  expect_near(sun_towards(9.0), {0.70711, 0.55873, 0.43340}, 1e-5, "9:00");
  // 15:00 mirrors it to the west.
  expect_near(sun_towards(15.0), {-0.70711, 0.55873, 0.43340}, 1e-5, "15:00");
  // Sunrise at 6:00 due east, exactly level.
  expect_near(sun_towards(6.0), {1.0, 0.0, 0.0}, 1e-12, "6:00");
  EXPECT_EQ(sun_towards(6.0).y, 0.0);

  const Light noon = sky_light(12.0), midnight = sky_light(0.0), dawn = sky_light(6.0);
  EXPECT_EQ(noon.type, LightType::directional);
  expect_near(dvec3(noon.direction), {0.0, -0.79016, -0.61291}, 1e-5, "noon's rays");
  // At midnight the full moon stands where the sun stood at noon, dimmer and bluer.
  expect_near(dvec3(midnight.direction), dvec3(noon.direction), 1e-6, "midnight's rays");
  EXPECT_LT(midnight.intensity, noon.intensity / 1000.0f);
  EXPECT_GT(midnight.color.b, midnight.color.r);
  EXPECT_EQ(dawn.direction.y, 0.0f) << "at sunrise the light is level: no shadow";

  EXPECT_EQ(tod_hour_bits(0.0), 1u);
  EXPECT_EQ(tod_hour_bits(6.0), 1u << 3);
  EXPECT_EQ(tod_hour_bits(7.0), 1u << 3 | 1u << 4);
  EXPECT_EQ(tod_hour_bits(23.5), 1u << 11 | 1u);

  Scene scene;
  scene.lights.push_back(scene_kit::street_lamp({0.0, 5.0, 0.0}, 10.0f));
  set_hour(scene, 10.0);
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(scene.lights[0].type, LightType::directional) << "the sun goes first when the scene has none";
  set_hour(scene, 20.0);
  EXPECT_EQ(scene.lights.size(), 2u) << "the sun is replaced, not added again";
  EXPECT_THROW(set_hour(scene, 24.0), SceneError);
  EXPECT_THROW(set_hour(scene, -1.0), SceneError);
}

TEST(TimeOfDay, BakeIsDeterministicAndHidesCasters) {
  const Scene map = build_map({3, 1.0, Shot::street});
  TodBakeOptions one;
  one.threads = 1;
  const TodTable a = bake_tod(map, 3, 1.0), b = bake_tod(map, 3, 1.0, one);
  ASSERT_EQ(a.visible.size(), map.instances.size());
  EXPECT_TRUE(a.visible == b.visible) << "the bake differs between runs (2 threads and 1)";
  for (uint32_t slot = 0; slot < kTodHours; ++slot) {
    size_t hidden = 0;
    for (uint16_t bits : a.visible) hidden += !(bits >> slot & 1);
    std::printf("%02u:00: %zu of %zu instances hidden from the light\n", slot * 2, hidden, a.visible.size());
    EXPECT_GT(hidden, 0u);
    EXPECT_LT(hidden, a.visible.size() / 2);
  }
  size_t moving = 0;
  for (size_t i = 0; i < map.instances.size(); ++i) {
    if (!map.instances[i].moving) continue;
    ++moving;
    EXPECT_EQ(a.visible[i], kTodAllHours) << "a moving instance is never hidden";
  }
  EXPECT_GT(moving, 0u) << "the map has traffic and pedestrians: the check above ran";
}

class TodFile : public ::testing::Test {
 protected:
  const Scene map = build_map({5, 0.5, Shot::street});
  TodTable table() const {
    TodTable t;
    t.seed = 5;
    t.map_size_km = 0.5;
    t.scene_hash = tod_scene_hash(map);
    t.visible.assign(map.instances.size(), 0x0F0F);
    return t;
  }
  // The error read_tod throws for the file, or "" when it reads.
  std::string error_of(const std::filesystem::path& file, uint32_t seed = 5, double size = 0.5) const {
    try {
      read_tod(file, seed, size, map);
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << "the message names the file";
      return e.what();
    }
    return "";
  }
  static std::vector<char> bytes_of(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write(const std::filesystem::path& file, const std::vector<char>& bytes) {
    std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  }
};

TEST_F(TodFile, RoundTripsAndRefusesBadFiles) {
  ScratchFolder scratch("tod-file");
  const auto good = scratch.path / "map.tod";
  write_tod(table(), good);
  EXPECT_EQ(read_tod(good, 5, 0.5, map).visible, table().visible);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(scratch.path), {}), 1) << "no temporary file left";
  const std::vector<char> bytes = bytes_of(good);

  auto variant = [&](const char* name, auto change) {
    std::vector<char> b = bytes;
    change(b);
    const auto file = scratch.path / name;
    write(file, b);
    return error_of(file);
  };
  EXPECT_NE(variant("truncated.tod", [](auto& b) { b.pop_back(); }).find("truncated"), std::string::npos);
  EXPECT_NE(variant("header.tod", [](auto& b) { b.resize(20); }).find("truncated"), std::string::npos);
  EXPECT_NE(variant("corrupt.tod", [](auto& b) { b[80] ^= 0x40; }).find("corrupt"), std::string::npos);
  EXPECT_NE(variant("magic.tod", [](auto& b) { b[0] = 'X'; }).find("not a time-of-day table"), std::string::npos);
  EXPECT_NE(variant("version.tod", [](auto& b) { b[8] = 9; }).find("version 9"), std::string::npos);
  EXPECT_NE(variant("empty.tod", [](auto& b) { b.clear(); }).find("not a time-of-day table"), std::string::npos);
  EXPECT_NE(error_of(scratch.path / "missing.tod").find("cannot read"), std::string::npos);

  EXPECT_NE(error_of(good, 6, 0.5).find("seed 5"), std::string::npos) << "another seed";
  EXPECT_NE(error_of(good, 5, 1.0).find("0.5 km"), std::string::npos) << "another size";
  TodTable other = table();
  other.scene_hash = tod_scene_hash(build_map({6, 0.5, Shot::street}));
  write_tod(other, scratch.path / "other.tod");
  EXPECT_NE(error_of(scratch.path / "other.tod").find("instances differ"), std::string::npos);
}

class TodShadows : public GpuTest {
 protected:
  struct Sun {
    std::vector<uint8_t> visibility;  // shadow.sun's R
    ShadowCullStats stats{};
  };
  static Sun render(Scene scene, const TodTable* table, double hour) {
    set_hour(scene, hour);
    if (table) {
      scene.tod_visible = table->visible;
      scene.tod_hour = hour;
    }
    RenderSettings settings;
    settings.width = 640;
    settings.height = 360;
    settings.path.motion = CameraPath::Motion::still;
    settings.sinks = {"shadow.sun"};
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    const RecordedPass cull = recorded_pass(frame, "shadow.cull");
    Sun sun;
    const auto& rg = *frame.execution.final_version("shadow.sun")->bytes;
    for (size_t i = 0; i < rg.size(); i += 2) sun.visibility.push_back(rg[i]);
    std::memcpy(&sun.stats, cull.outputs.at("shadow.cull_stats").bytes->data(), sizeof(sun.stats));
    return sun;
  }
};

// The street and rooftop shots of a 1 km map, at baked hours and between them, by the sun and
// by the moon: of the pixels in
// shadow (visibility below 1) with the filter or without, the share where both agree.
TEST_F(TodShadows, FilteredShadowAgreesWithUnfiltered) {
  const TodTable table = bake_tod(build_map({3, 1.0, Shot::street}), 3, 1.0);
  uint32_t dropped_total = 0;
  for (Shot shot : {Shot::street, Shot::rooftop}) {
    const Scene scene = build_map({3, 1.0, shot});
    // By day, baked and between; 7:00 between sunrise (level light, baked from both sides) and
    // 8:00; 21:00 by the moon.
    for (double hour : {8.0, 10.0, 16.0, 9.0, 15.0, 7.0, 21.0}) {
      const Sun full = render(scene, nullptr, hour), filtered = render(scene, &table, hour);
      size_t shadowed = 0, agree = 0;
      for (size_t i = 0; i < full.visibility.size(); ++i) {
        if (full.visibility[i] == 255 && filtered.visibility[i] == 255) continue;
        ++shadowed;
        agree += full.visibility[i] == filtered.visibility[i];
      }
      uint32_t dropped = 0, saved = 0, drawn = 0;
      for (uint32_t k = 0; k < kShadowCascades; ++k) {
        dropped += filtered.stats.casters_tod_dropped[k];
        saved += filtered.stats.tod_triangles_saved[k];
        drawn += filtered.stats.triangles[k];
        EXPECT_EQ(full.stats.casters_tod_dropped[k], 0u);
      }
      dropped_total += dropped;
      const double share = shadowed ? double(agree) / shadowed : 1.0;
      const bool baked = std::fmod(hour, kTodHourStep) == 0.0;
      std::printf(
          "%s shot, %04.1f h: %zu of %zu shadowed pixels agree (%.4f%%); %u casters dropped, %u of %u "
          "triangles saved\n",
          shot_name(shot).c_str(), hour, agree, shadowed, 100.0 * share, dropped, saved, saved + drawn);
      EXPECT_GT(shadowed, 1000u) << "the view must hold shadow for the comparison to mean something";
      EXPECT_GE(share, baked ? 0.999 : 0.99) << shot_name(shot) << " at " << hour << " h";
    }
  }
  EXPECT_GT(dropped_total, 0u) << "the filter must drop casters for the comparison to mean something";
}

// Stress: a table that hides every static caster at 22:00 and 0:00, read at 23:30 (the union
// across midnight): only the moving casters are drawn, and shadow.cull run again on its recorded
// inputs writes the same bytes (what replay --verify checks). A scene.tod of the wrong size is
// refused with a message naming it.
TEST_F(TodShadows, EveryStaticCasterDroppedAcrossMidnightReplays) {
  Scene scene = build_map({1, 0.5, Shot::street});
  set_hour(scene, 23.5);
  scene.tod_hour = 23.5;
  size_t moving = 0;
  for (const Instance& instance : scene.instances) {
    scene.tod_visible.push_back(instance.moving ? kTodAllHours : uint16_t(kTodAllHours & ~(1u << 11 | 1u)));
    moving += instance.moving;
  }
  ASSERT_GT(moving, 0u);
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.path.motion = CameraPath::Motion::still;
  settings.sinks = {"shadow.sun"};
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  EXPECT_EQ(first_non_finite(frame.execution), "");
  const RecordedPass cull = recorded_pass(frame, "shadow.cull");
  ASSERT_FALSE(cull.outputs.empty()) << "the moon is up at 23:30: shadow.cull runs";
  ShadowCullStats stats{};
  std::memcpy(&stats, cull.outputs.at("shadow.cull_stats").bytes->data(), sizeof(stats));
  const auto draws = host_records<GpuDraw>(*cull.outputs.at("draws.shadow.cascades").bytes);
  uint32_t dropped = 0;
  for (uint32_t k = 0; k < kShadowCascades; ++k) dropped += stats.casters_tod_dropped[k];
  EXPECT_GT(dropped, 0u);
  for (const GpuDraw& d : draws) EXPECT_TRUE(scene.instances.at(d.instance).moving) << "instance " << d.instance;
  const IsolatedRun again = run(shadow_cull_pass(), cull.inputs, settings.width, settings.height);
  for (const auto& [name, output] : cull.outputs)
    EXPECT_TRUE(*again.outputs.at(name) == *output.bytes) << name << " differs when run again";

  auto inputs = cull.inputs;
  auto shorter = std::make_shared<std::vector<uint8_t>>(*inputs.at("scene.tod").bytes);
  shorter->resize(shorter->size() - 4);
  inputs.at("scene.tod").bytes = shorter;
  inputs.at("scene.tod").desc.buffer_size = shorter->size();
  try {
    run(shadow_cull_pass(), inputs, settings.width, settings.height);
    ADD_FAILURE() << "a scene.tod without a mask for every instance ran";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("scene.tod"), std::string::npos) << e.what();
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
