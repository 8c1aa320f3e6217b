// The sun's shadow (shadow.cull, shadow.cascades, shadow.sun_resolve) against a CPU ray cast of
// the scene's triangles in double precision (tests/reference/shadow_reference.h). Bounds, from
// shared/design/accuracy.md:
// - agreement: at pixels facing the sun (n·l > 0.1), closer than the last split and more than 2
//   cascade texels (measured across the sun's rays) from an edge of the ray cast's shadow, the
//   pass's visibility (R ≥ 0.5 lit) agrees with the ray cast at ≥ 99% of them;
// - acne: a plane lit at incidence 0–80° has no texel of shadow.sun below 1;
// - peter-panning: behind a thin wall standing on a plane, the ground the ray cast shadows but
//   the pass calls lit lies within 1 texel of the wall;
// (the acne and peter-panning tests also break their own bound on purpose, to show they can see
// a failure);
// - culling (shadow.cull.culling on and off) leaves shadow.sun bit-identical;
// - caching (shadow.cull.cache on and off) leaves shadow.sun bit-identical over frames 0-4 of a
//   still camera (vehicles moving), which redraws no static tile from frame 1 on, and the same
//   at ≥ 99.9% of the pixels of a driving one; each shadow pass of frame 3 replays from its
//   record;
// - driving: the static layers' complete tiles hold a fresh render's depth within 1 mm at
//   ≥ 99.9% of their texels; with a small budget each frame's static draws stay within it, tiles
//   wait, and the shadow (falling back to coarser maps there) still agrees with the ray cast;
// - stress (the sun at the horizon, straight down, a caster around the camera, the map's far
//   corner): every float output finite, and each shadow pass run again on its recorded inputs
//   writes the same bytes (what replay --verify checks).
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>

#include "passes/assembly/renderer.h"
#include "passes/frame/gpu_types.h"
#include "passes/scene/scene_kit.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/stage.h"
#include "tests/reference/shadow_reference.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/recorded_pass.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;
using reference::ShadowAgreement;
using reference::ShadowTriangles;
using reference::ShadowView;

// A frame's shadow passes: what each read and wrote, the resolve decoded.
struct Frame {
  RecordedPass cull, statics, map, resolve;
  std::optional<ShadowView> view;
  ShadowCullStats stats{};
  std::string non_finite;
  dvec3 eye{0.0};
  uint32_t width = 0, height = 0;
};

Scene with_sun(Scene scene, const glm::vec3& direction) {
  for (Light& light : scene.lights)
    if (light.type == LightType::directional) {
      light.direction = glm::normalize(direction);
      return scene;
    }
  Light sun = scene_kit::moon();
  sun.direction = glm::normalize(direction);
  scene.lights.insert(scene.lights.begin(), sun);
  return scene;
}

// A ground plane (its top at y = 0) with boxes standing on it, lit by the sun, seen from
// `eye` looking at `target`.
Scene plane_scene(const std::vector<std::pair<dvec3, dvec3>>& boxes, const glm::vec3& sun, const dvec3& eye,
                  const dvec3& target) {
  Scene scene;
  scene.source = "shadow reference";
  scene_kit::Builder build(scene);
  const uint32_t grey = build.material(scene_kit::plain("ground", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
  build.place(build.box(glm::vec3(40.0f, 0.05f, 40.0f), grey, 1.0f, true, true), {0.0, -0.05, 0.0});
  for (const auto& [centre, half] : boxes) build.place(build.box(glm::vec3(half), grey, 1.0f, true, true), centre);
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  camera.world = glm::inverse(glm::lookAt(eye, target, dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  return with_sun(scene, sun);
}

Scene moved(Scene scene, const dvec3& offset) {
  for (Instance& instance : scene.instances) instance.world[3] += glm::dvec4(offset, 0.0);
  for (Light& light : scene.lights) {
    light.position += offset;
    light.end += offset;
  }
  if (scene.camera) scene.camera->world[3] += glm::dvec4(offset, 0.0);
  return scene;
}

class Shadows : public GpuTest {
 protected:
  static Frame frame_of(const RenderedFrame& rendered, uint32_t width, uint32_t height) {
    Frame f;
    f.width = width;
    f.height = height;
    f.non_finite = first_non_finite(rendered.execution);
    f.cull = recorded_pass(rendered, "shadow.cull");
    f.statics = recorded_pass(rendered, "shadow.cascades_static");
    f.map = recorded_pass(rendered, "shadow.cascades");
    f.resolve = recorded_pass(rendered, "shadow.sun_resolve");
    if (f.resolve.outputs.empty()) {
      ADD_FAILURE() << "shadow.sun_resolve did not run";
      return f;
    }
    f.view.emplace(f.resolve.inputs, f.resolve.outputs.at("shadow.sun"));
    std::memcpy(&f.stats, f.cull.outputs.at("shadow.cull_stats").bytes->data(), sizeof(f.stats));
    return f;
  }

  static Frame render(const Scene& scene, uint32_t width, uint32_t height,
                      std::map<std::string, ParamValues> params = {}) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = CameraPath::Motion::still;
    settings.sinks = {"shadow.sun"};
    settings.params = std::move(params);
    Renderer renderer(*gpu_, scene, settings);
    Frame f = frame_of(renderer.render_frame(0, true), width, height);
    f.eye = dvec3(base_camera(scene, settings).world[3]);
    return f;
  }

  // Frames 0 to count - 1 of the camera's `motion`.
  static std::vector<Frame> render_frames(const Scene& scene, CameraPath::Motion motion, uint32_t count,
                                          std::map<std::string, ParamValues> params) {
    RenderSettings settings;
    settings.width = 320;
    settings.height = 180;
    settings.path.motion = motion;
    settings.sinks = {"shadow.sun"};
    settings.params = std::move(params);
    Renderer renderer(*gpu_, scene, settings);
    std::vector<Frame> frames;
    for (uint32_t i = 0; i < count; ++i) frames.push_back(frame_of(renderer.render_frame(i, true), 320, 180));
    return frames;
  }

  static void expect_agreement(const char* name, const Scene& scene, const Frame& f, uint32_t stride) {
    ASSERT_TRUE(f.view);
    const ShadowAgreement a = reference::shadow_agreement(*f.view, ShadowTriangles(scene, f.eye), stride);
    std::printf("%s: %zu of %zu sampled pixels agree with the ray cast (%.3f%%; %zu ray-shadowed), %zu near an edge\n",
                name, a.agreed, a.compared, 100.0 * a.share(), a.ray_shadowed, a.near_edge);
    EXPECT_GT(a.compared, 500u);
    EXPECT_GT(a.ray_shadowed, 50u) << "the test needs shadows to compare";
    EXPECT_GE(a.share(), 0.99) << a.first_disagreement;
  }

  // Each shadow pass run again on the inputs the frame recorded for it writes the same bytes.
  static void expect_replays(const Frame& f, const std::map<std::string, ParamValues>& params = {}) {
    for (const auto& [decl, r] :
         {std::pair{shadow_cull_pass(), &f.cull}, std::pair{shadow_cascades_static_pass(), &f.statics},
          std::pair{shadow_cascades_pass(), &f.map}, std::pair{shadow_sun_resolve_pass(), &f.resolve}}) {
      const auto set = params.find(decl.name);
      const IsolatedRun again =
          run(decl, r->inputs, f.width, f.height, set == params.end() ? ParamValues{} : set->second);
      for (const auto& [name, output] : r->outputs)
        EXPECT_TRUE(*again.outputs.at(name) == *output.bytes) << decl.name << ": " << name << " differs when run again";
    }
  }
};

const glm::vec3 kSun(0.35f, -0.8f, 0.45f);

TEST_F(Shadows, BoxesOnAPlaneAgreeWithARayCast) {
  const Scene scene = plane_scene({{{0.0, 1.0, 0.0}, {1.0, 1.0, 1.0}},
                                   {{-4.0, 0.25, 3.0}, {0.5, 0.25, 2.0}},
                                   {{5.0, 3.0, -6.0}, {1.5, 3.0, 1.5}},
                                   {{-8.0, 0.6, -12.0}, {3.0, 0.6, 0.4}}},
                                  kSun, {6.0, 6.0, 14.0}, {-1.0, 0.0, -2.0});
  const Frame f = render(scene, 640, 360);
  EXPECT_EQ(f.non_finite, "");
  expect_agreement("boxes on a plane", scene, f, 3);
}

TEST_F(Shadows, CityAgreesWithARayCast) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  const Frame f = render(scene, 640, 360);
  EXPECT_EQ(f.non_finite, "");
  expect_agreement("city", scene, f, 3);
}

// A plane lit at incidence up to 80°, nothing else: no texel of shadow.sun may be below 1. The
// same plane without the receiver-plane bias (max_slope 0, depth_bias 0) has acne at 80°: the
// test can see it.
TEST_F(Shadows, NoAcneUpTo80DegreesIncidence) {
  auto shadowed_pixels = [&](double degrees, std::map<std::string, ParamValues> params) {
    const double a = glm::radians(degrees);
    // Turned about the vertical so the sun does not line up with the map's axes.
    const glm::vec3 sun(float(std::sin(a) * 0.8), float(-std::cos(a)), float(std::sin(a) * 0.6));
    const Scene scene = plane_scene({}, sun, {0.0, 3.0, 10.0}, {0.0, 0.0, -20.0});
    const Frame f = render(scene, 320, 180, std::move(params));
    EXPECT_EQ(f.non_finite, "");
    size_t pixels = 0, shadowed = 0;
    if (!f.view) return std::pair{pixels, shadowed};
    const ShadowView& v = *f.view;
    for (uint32_t y = 0; y < v.height; ++y)
      for (uint32_t x = 0; x < v.width; ++x) {
        const auto s = v.surface(x, y);
        if (!s || s->view_depth > v.cascades.splits[3]) continue;
        ++pixels;
        shadowed += v.visibility(x, y) < 1.0;
      }
    return std::pair{pixels, shadowed};
  };
  for (double degrees : {0.0, 30.0, 60.0, 70.0, 80.0}) {
    const auto [pixels, shadowed] = shadowed_pixels(degrees, {});
    std::printf("incidence %.0f°: %zu of %zu plane pixels shadowed\n", degrees, shadowed, pixels);
    EXPECT_GT(pixels, 10000u);
    EXPECT_EQ(shadowed, 0u) << "acne at " << degrees << "°";
  }
  const auto [pixels, shadowed] =
      shadowed_pixels(80.0, {{"shadow.sun_resolve", {{"max_slope", 0.0}, {"depth_bias", 0.0}}}});
  std::printf("incidence 80° without the bias: %zu of %zu plane pixels shadowed\n", shadowed, pixels);
  EXPECT_GT(shadowed, pixels / 10) << "without its bias the plane should shadow itself";
}

// A thin wall (4 cm) standing on the plane, a low sun: the ground behind it that the ray cast
// shadows and the pass lights (the gap between the contact and the shadow) lies within 1 texel
// of the wall. With a depth bias of 16 texels the gap opens wider than a texel: the test sees it.
TEST_F(Shadows, PeterPanningAtMostOneTexel) {
  const dvec3 half(1.0, 0.3, 0.02);
  auto gap_behind = [&](double elevation, std::map<std::string, ParamValues> params) {
    const double e = glm::radians(elevation);
    const glm::vec3 sun(0.0f, float(-std::sin(e)), float(-std::cos(e)));  // toward -z: the shadow falls there
    // Seen from the shadow's side, so the ground behind the wall is in view.
    const Scene scene = plane_scene({{{0.0, half.y, 0.0}, half}}, sun, {2.0, 2.5, -4.0}, {0.0, 0.0, -0.8});
    const Frame f = render(scene, 640, 360, std::move(params));
    EXPECT_EQ(f.non_finite, "");
    double gap = 0.0, texel = 0.0;
    size_t behind = 0;
    if (!f.view) return std::tuple{gap, texel, behind};
    const ShadowView& v = *f.view;
    const ShadowTriangles triangles(scene, f.eye);
    const dvec3 l = v.to_sun();
    const double back = -half.z, length = 2 * half.y / std::tan(e);
    for (uint32_t y = 0; y < v.height; ++y)
      for (uint32_t x = 0; x < v.width; ++x) {
        const auto s = v.surface(x, y);
        if (!s || s->normal.y < 0.99) continue;
        const dvec3 world = s->position + f.eye;
        const double pixel_texel = v.cascades.texel_metres[v.cascade_of(s->view_depth)];
        // On the ground, behind the wall, away from the shadow's sides, in its first half.
        const double from_wall = back - world.z;
        if (world.y > 0.01 || from_wall < 0 || from_wall > 0.5 * length || std::abs(world.x) > half.x - 3 * pixel_texel)
          continue;
        ++behind;
        texel = std::max(texel, pixel_texel);
        if (!triangles.lit(s->position, s->normal, l, s->view_depth) && v.visibility(x, y) >= 0.5)
          gap = std::max(gap, from_wall);
      }
    return std::tuple{gap, texel, behind};
  };
  for (double elevation : {20.0, 45.0}) {
    const auto [gap, texel, behind] = gap_behind(elevation, {});
    std::printf("sun %.0f° up: gap %.4f m behind the wall (a texel is %.4f m), %zu ground pixels behind it\n",
                elevation, gap, texel, behind);
    EXPECT_GT(behind, 200u);
    EXPECT_LE(gap, texel);
  }
  const auto [gap, texel, behind] = gap_behind(20.0, {{"shadow.sun_resolve", {{"depth_bias", 16.0}}}});
  std::printf("sun 20° up, depth_bias 16: gap %.4f m (a texel is %.4f m)\n", gap, texel);
  EXPECT_GT(gap, texel) << "a large bias should open a gap the test sees";
}

// Culling (by the cascades' volumes, the view's occluders and shadow.distant_occluders from the
// sun) drops no caster that changes the shadow: shadow.sun is bit-identical with it off, on the city and on the street
// shot of a 2 km map (levels of detail, traffic).
TEST_F(Shadows, CullingChangesNoShadow) {
  Scene city = build_city(1);
  add_default_lighting(city);
  Scene street = build_map({1, 2.0, Shot::street});
  add_default_lighting(street);
  for (const auto& [name, scene] : {std::pair{"city", &city}, std::pair{"2 km map, street", &street}}) {
    SCOPED_TRACE(name);
    // With the cache off, so that the view's occluders may hide static casters too.
    const Frame on = render(*scene, 640, 360, {{"shadow.cull", {{"cache", 0}}}});
    const Frame off = render(*scene, 640, 360, {{"shadow.cull", {{"culling", 0}, {"cache", 0}}}});
    ASSERT_TRUE(on.view && off.view);
    uint32_t culled = 0, hidden = 0, light_hidden = 0, tested = 0;
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      culled += on.stats.casters_culled[k];
      hidden += on.stats.casters_hidden[k];
      light_hidden += on.stats.casters_light_hidden[k];
      tested += on.stats.casters_tested[k];
      std::printf(
          "%s, cascade %u: %u casters tested, %u culled, %u hidden, %u behind the sun's occluders, %u drawn, %u "
          "planes, ends at %.1f m, texel %.4f m\n",
          name, k, on.stats.casters_tested[k], on.stats.casters_culled[k], on.stats.casters_hidden[k],
          on.stats.casters_light_hidden[k], on.stats.draws[k], on.stats.planes[k], on.view->cascades.splits[k],
          on.view->cascades.texel_metres[k]);
      EXPECT_LE(on.stats.planes[k], 8u);
      EXPECT_EQ(off.stats.draws[k], off.stats.casters_tested[k]);
    }
    EXPECT_GT(culled + hidden, tested / 4) << "culling must remove casters for the comparison to mean something";
    if (scene == &street) {
      EXPECT_GT(hidden, 0u) << "the view's occluders must hide some shadow, so the test covers them";
      EXPECT_GT(light_hidden, 0u) << "the sun's occluders must hide some caster, so the test covers them";
    }
    EXPECT_TRUE(*on.resolve.outputs.at("shadow.sun").bytes == *off.resolve.outputs.at("shadow.sun").bytes)
        << "shadow.sun differs with culling off";
  }
}

TEST_F(Shadows, CachingChangesNoShadowAcrossFrames) {
  Scene street = build_map({1, 2.0, Shot::street});
  add_default_lighting(street);
  for (const CameraPath::Motion motion : {CameraPath::Motion::still, CameraPath::Motion::drive}) {
    const bool still = motion == CameraPath::Motion::still;
    SCOPED_TRACE(still ? "still camera" : "driving");
    // The street's cars are all in the buildings' shadow seen from the sun: without the sun's
    // occluders culling them, they are drawn over the kept static depth.
    const std::vector<Frame> on = render_frames(street, motion, 5, {{"shadow.cull", {{"light_occlusion", 0}}}});
    const std::vector<Frame> off =
        render_frames(street, motion, 5, {{"shadow.cull", {{"cache", 0}, {"light_occlusion", 0}}}});
    uint32_t moving = 0;
    for (uint32_t i = 0; i < on.size(); ++i) {
      ASSERT_TRUE(on[i].view && off[i].view);
      const ShadowCullStats& stats = on[i].stats;
      std::printf(
          "%s, frame %u: reset %u, %u static triangles, %u level changes; per cascade shift, strips, tiles "
          "redrawn:",
          still ? "still" : "driving", i, stats.reset, stats.static_triangles, stats.level_changes);
      uint64_t refreshed = stats.strips;
      for (uint32_t k = 0; k < kShadowCascades; ++k) {
        std::printf(" (%d, %d) %u %d", stats.shift[2 * k], stats.shift[2 * k + 1], stats.strips >> k & 1u,
                    std::popcount(ShadowCullStats::mask(stats.refreshed, k)));
        refreshed |= ShadowCullStats::mask(stats.refreshed, k);
        moving += stats.moving_draws[k];
      }
      EXPECT_EQ(off[i].stats.reset, uint32_t(CascadeReset::cache_off));
      EXPECT_EQ(stats.reset, uint32_t(i == 0 ? CascadeReset::no_history : CascadeReset::none)) << "frame " << i;
      EXPECT_EQ(stats.pending, 0u) << "frame " << i << ": the default budget keeps up";
      if (i > 0) {
        EXPECT_EQ(refreshed != 0, !still) << "frame " << i << ": only a moving camera redraws static tiles";
      }
      EXPECT_EQ(on[i].non_finite, "");
      // shadow.cascades itself differs: with the cache on, a tile holds every static caster across
      // the sun from it, not only those the slice's volume and the view keep (cull.cpp says why
      // that changes no shadow). A still camera's shadow is the same bytes; a driving one's
      // layers hold texels drawn in earlier frames, from another eye: the camera-relative
      // vertices round differently, so a texel's depth may differ in its last bits, or a
      // triangle's edge cover a texel more or less.
      const std::vector<uint8_t>& a = *on[i].resolve.outputs.at("shadow.sun").bytes;
      const std::vector<uint8_t>& b = *off[i].resolve.outputs.at("shadow.sun").bytes;
      ASSERT_EQ(a.size(), b.size());
      size_t differing = 0;
      for (size_t p = 0; p < a.size(); p += 2) differing += a[p] != b[p];
      std::printf("; %zu of %zu pixels differ from the cache off\n", differing, a.size() / 2);
      if (still)
        EXPECT_EQ(differing, 0u) << "frame " << i << ": shadow.sun differs with the cache off";
      else
        EXPECT_LE(differing, a.size() / 2 / 1000) << "frame " << i << ": more than 0.1% of shadow.sun differs";
    }
    EXPECT_GT(moving, 0u) << "the test needs moving casters over the kept static depth";
    if (still) {
      ASSERT_TRUE(on[3].statics.inputs.count(previous("shadow.cascades_static")));
      EXPECT_TRUE(*on[3].statics.inputs.at(previous("shadow.cascades_static")).bytes ==
                  *on[2].statics.outputs.at("shadow.cascades_static").bytes)
          << "frame 3 reads frame 2's static depth";
    }
    expect_replays(on[3], {{"shadow.cull", {{"light_occlusion", 0}}}});
  }
}

// Driving, the static layers' complete tiles (carried over and moved, or redrawn) hold what a
// renderer starting at that frame, with no history, draws there: at every texel the same depth
// within 1 mm, except where a triangle's edge covers a texel in one and not the other (at most
// 0.1% of the texels compared). On the street, and on a plane where a caster switches to its
// finer level of detail as the camera drives toward it (its tiles must be redrawn).
TEST_F(Shadows, DrivingKeepsTheStaticLayersAsAFreshRenderDrawsThem) {
  Scene street = build_map({1, 2.0, Shot::street});
  add_default_lighting(street);
  // A wall 4 m wide whose coarser level is a pole 6 m tall, beyond 9.5 m from the camera: the
  // camera starts 10.2 m from it and drives 0.23 m a frame toward it.
  Scene levels = plane_scene({}, {0.5f, -1.0f, 0.3f}, {0.0, 3.0, 8.0}, {0.0, 0.0, -4.0});
  {
    scene_kit::Builder build(levels);
    const uint32_t grey = build.material(scene_kit::plain("wall", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
    const uint32_t wall = build.box(glm::vec3(2.0f, 1.0f, 0.1f), grey, 1.0f, true, true);
    const uint32_t pole = build.box(glm::vec3(0.1f, 3.0f, 0.1f), grey, 1.0f, true, true);
    levels.primitives[wall].coarser = int32_t(pole);
    levels.primitives[wall].lod_distance = 9.5f;
    build.place(wall, {0.0, 1.0, -2.0});
  }
  constexpr uint32_t kLast = 7;
  for (const auto& [name, scene] : {std::pair{"street", &street}, std::pair{"a caster changing its level", &levels}}) {
    SCOPED_TRACE(name);
    const std::vector<Frame> driven = render_frames(*scene, CameraPath::Motion::drive, kLast + 1, {});
    RenderSettings settings;
    settings.width = 320;
    settings.height = 180;
    settings.path.motion = CameraPath::Motion::drive;
    settings.sinks = {"shadow.sun"};
    Renderer renderer(*gpu_, *scene, settings);
    const Frame fresh = frame_of(renderer.render_frame(kLast, true), 320, 180);
    ASSERT_EQ(fresh.stats.reset, uint32_t(CascadeReset::no_history));
    const Frame& carried = driven[kLast];
    ASSERT_EQ(carried.stats.reset, uint32_t(CascadeReset::none));
    uint32_t redrawn = 0, level_changes = 0;
    for (uint32_t i = 1; i <= kLast; ++i) {
      level_changes += driven[i].stats.level_changes;
      redrawn += std::popcount(driven[i].stats.strips);
      for (uint32_t k = 0; k < kShadowCascades; ++k)
        redrawn += std::popcount(ShadowCullStats::mask(driven[i].stats.refreshed, k));
    }
    std::printf("%s: %u units (strips, tiles) redrawn over frames 1-%u, %u level changes\n", name, redrawn, kLast,
                level_changes);
    EXPECT_GT(redrawn, 0u) << "the drive must move the layers";
    if (scene == &levels) {
      EXPECT_EQ(level_changes, 1u) << "the wall must change its level during the drive";
    }

    const std::vector<uint8_t>& a = *carried.statics.outputs.at("shadow.cascades_static").bytes;
    const std::vector<uint8_t>& b = *fresh.statics.outputs.at("shadow.cascades_static").bytes;
    ASSERT_EQ(a.size(), b.size());
    const uint32_t n = carried.stats.resolution, tiles = carried.stats.tiles_per_side, side = n / tiles;
    ASSERT_EQ(a.size(), size_t(n) * n * kShadowCascades * sizeof(float));
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      const uint64_t both =
          ShadowCullStats::mask(carried.stats.complete, k) & ShadowCullStats::mask(fresh.stats.complete, k);
      const double metres = carried.view->cascades.depth_metres[k];
      EXPECT_EQ(metres, fresh.view->cascades.depth_metres[k]);
      size_t compared = 0, off = 0;
      double largest = 0.0;
      for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
          if (!(both >> ((y / side) * tiles + x / side) & 1u)) continue;
          float p, q;
          const size_t at = (size_t(k) * n * n + size_t(y) * n + x) * sizeof(float);
          std::memcpy(&p, a.data() + at, sizeof p);
          std::memcpy(&q, b.data() + at, sizeof q);
          ++compared;
          const double error = std::abs(double(p) - double(q)) * metres;
          if (error > 1e-3)
            ++off;
          else
            largest = std::max(largest, error);
        }
      std::printf(
          "  cascade %u: %zu texels of %d complete tiles compared, %zu differ by more than 1 mm, the others "
          "by %.2e m at most\n",
          k, compared, std::popcount(both), off, largest);
      EXPECT_GT(compared, size_t(side) * side) << "cascade " << k;
      EXPECT_LE(off, compared / 1000) << "cascade " << k;
    }
  }
}

// With a budget below what the driving camera uncovers, stale tiles wait over frames: each
// frame's static draws stay within it (or one unit above it, alone), tiles are pending, and the
// pixels whose own cascade is not complete there fall back to a coarser map: the shadow still
// agrees with the ray cast as accuracy.md asks (≥ 99%).
TEST_F(Shadows, CascadesRefreshWithinTheBudgetWhileDriving) {
  Scene street = build_map({1, 2.0, Shot::street});
  add_default_lighting(street);
  constexpr uint32_t kBudget = 20000, kFrames = 8;
  const std::vector<Frame> frames =
      render_frames(street, CameraPath::Motion::drive, kFrames, {{"shadow.cull", {{"budget_triangles", kBudget}}}});
  uint32_t most_pending = 0, worst = 0, longest = 0;
  std::array<uint32_t, kShadowCascades> tiles_redrawn{};
  for (uint32_t i = 0; i < kFrames; ++i) {
    const ShadowCullStats& stats = frames[i].stats;
    uint32_t units = std::popcount(stats.strips), waited = 0;
    for (uint32_t k = 0; k < kShadowCascades; ++k) {
      const uint32_t tiles = std::popcount(ShadowCullStats::mask(stats.refreshed, k));
      units += tiles;
      if (i > 0) tiles_redrawn[k] += tiles;
    }
    for (uint32_t u = 0; u < kCascadeUnits; ++u) waited = std::max(waited, stats.unit_waiting[u]);
    std::printf(
        "frame %u: %u units redrawn (%d strips), %u static triangles, %u pending, the longest wait %u "
        "frames, over budget %u\n",
        i, units, std::popcount(stats.strips), stats.static_triangles, stats.pending, waited, stats.over_budget);
    EXPECT_EQ(frames[i].non_finite, "");
    EXPECT_LT(waited, std::max(i, 1u)) << "frame " << i << ": no tile waits from before the reset";
    longest = std::max(longest, waited);
    if (i == 0) continue;
    EXPECT_TRUE(stats.static_triangles <= kBudget || (stats.over_budget && units == 1)) << "frame " << i;
    if (stats.pending > most_pending) most_pending = stats.pending, worst = i;
  }
  ASSERT_GT(most_pending, 0u) << "the budget must leave tiles waiting for the test to mean something";
  EXPECT_GT(longest, 0u) << "tiles left waiting must count the frames";
  std::printf("tiles redrawn over frames 1-%u per cascade: %u, %u, %u, %u\n", kFrames - 1, tiles_redrawn[0],
              tiles_redrawn[1], tiles_redrawn[2], tiles_redrawn[3]);
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.path.motion = CameraPath::Motion::drive;
  Frame f = frames[worst];
  f.eye = dvec3(frame_camera(base_camera(street, settings), street, settings.path, worst).world[3]);
  expect_agreement("driving, the frame with the most tiles pending", street, f, 2);
  expect_replays(f, {{"shadow.cull", {{"budget_triangles", kBudget}}}});
}

TEST_F(Shadows, StressStaysFiniteAndReplaysIdentically) {
  Scene city = build_city(1);
  add_default_lighting(city);
  RenderSettings probe;
  probe.width = 320;
  probe.height = 180;
  const Camera camera = base_camera(city, probe);
  // A box around the camera: its inside faces touch the near plane.
  Scene touching = city;
  {
    scene_kit::Builder build(touching);
    const uint32_t m = build.material(scene_kit::plain("around", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
    build.place(build.box(glm::vec3(0.3f, 0.3f, 0.3f), m, 1.0f, true, true), dvec3(camera.world[3]) + dvec3(0.2, 0, 0));
  }
  const std::vector<std::pair<const char*, Scene>> cases = {
      {"sun at the horizon", with_sun(city, {1.0f, -1e-3f, 0.3f})},
      {"sun straight down", with_sun(city, {0.0f, -1.0f, 0.0f})},
      {"caster touching the camera", touching},
      {"map's far corner", moved(build_map({1, 1.0, Shot::street}), {7500.0, 0.0, 7500.0})}};
  for (const auto& [name, scene] : cases) {
    SCOPED_TRACE(name);
    const Frame f = render(scene, 320, 180);
    EXPECT_EQ(f.non_finite, "");
    ASSERT_TRUE(f.view);
    for (uint32_t k = 0; k < kShadowCascades; ++k)
      for (int c = 0; c < 16; ++c) EXPECT_TRUE(std::isfinite(glm::value_ptr(f.view->cascades.light_from_world[k])[c]));
    expect_replays(f);
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
