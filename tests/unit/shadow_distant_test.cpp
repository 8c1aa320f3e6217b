// The sun's distant shadow (shadow.distant_plan, shadow.distant, and shadow.sun_resolve beyond
// the last cascade) against a CPU ray cast in double precision (tests/reference/shadow_reference.h).
// Bounds:
// - agreement: at pixels beyond the last cascade's split facing the sun (n·l > 0.1), more than 2
//   texels of the level the resolve reads (measured across the sun's rays) from an edge of the
//   ray cast's shadow, the visibility (R ≥ 0.5 lit) agrees with the ray cast at ≥ 99% of them
//   (accuracy.md's shadow bound, with the level's texel in place of the cascade's);
// - refresh: after the camera jumps (no cut), the plan marks stale exactly the tiles covering
//   texels no complete tile held, redraws only stale ones, each frame within the budget (or one
//   unit alone), until none is pending; the levels then match a full render there (bit for bit
//   in the redrawn tiles, within a quarter texel of depth at all but 0.1% of texels elsewhere);
// - up to date: with a still camera nothing is redrawn after frame 0 and the levels keep the
//   previous frame's bytes; with `cache` 0 every level is redrawn each frame; no sun above the
//   horizon skips both passes;
// - a moved camera: the texels a level keeps are bit-identical to a full render at the new view;
// - replay: frame 2 of a driving camera, each distant pass run again on its recorded inputs
//   (the previous frame's levels included), writes the same bytes;
// - stress (the sun at the horizon, straight down, the map's far corner): finite, replays.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "passes/assembly/renderer.h"
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
using reference::ShadowTriangles;
using reference::ShadowView;

struct Frame {
  RecordedPass plan, levels, resolve;
  DistantPlan decision{};
  GpuDistantLevels data{};
  std::string non_finite;
  dvec3 eye{0.0};
  bool planned = false, ran = false;  // shadow.distant_plan and shadow.distant ran
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

// A 600 m ground (its top at y = 0) with boxes out to 200 m, seen from 8 m up looking along -z.
Scene field_scene(const glm::vec3& sun) {
  Scene scene;
  scene.source = "distant shadow reference";
  scene_kit::Builder build(scene);
  const uint32_t grey = build.material(scene_kit::plain("ground", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
  build.place(build.box(glm::vec3(300.0f, 0.5f, 300.0f), grey, 1.0f, true, true), {0.0, -0.5, 0.0});
  const std::vector<std::pair<dvec3, dvec3>> boxes = {
      {{-6.0, 2.0, -25.0}, {2.0, 2.0, 2.0}},   {{8.0, 4.0, -45.0}, {3.0, 4.0, 1.5}},
      {{-15.0, 3.0, -70.0}, {4.0, 3.0, 4.0}},  {{20.0, 6.0, -100.0}, {5.0, 6.0, 3.0}},
      {{-30.0, 5.0, -140.0}, {8.0, 5.0, 2.0}}, {{10.0, 8.0, -180.0}, {6.0, 8.0, 6.0}},
      {{40.0, 2.5, -60.0}, {2.0, 2.5, 10.0}},  {{-45.0, 10.0, -110.0}, {3.0, 10.0, 3.0}}};
  for (const auto& [centre, half] : boxes) build.place(build.box(glm::vec3(half), grey, 1.0f, true, true), centre);
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  camera.world = glm::inverse(glm::lookAt(dvec3(0.0, 8.0, 0.0), dvec3(0.0, 0.0, -60.0), dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  return with_sun(scene, sun);
}

const glm::vec3 kSun(0.35f, -0.8f, 0.45f);

// Cascades end at 10 m, so most of the view reads the distant levels.
std::map<std::string, ParamValues> distant_params(double budget, double tiles = 2) {
  return {{"shadow.cull", {{"max_distance", 10.0}}},
          {"shadow.distant_plan", {{"level0_metres", 128.0}, {"budget_triangles", budget}, {"tiles", tiles}}}};
}

class DistantShadows : public GpuTest {
 protected:
  // Frames 0 … count − 1 of `scene` in order (the history carried), each decoded.
  static std::vector<Frame> render(const Scene& scene, uint32_t count, std::map<std::string, ParamValues> params,
                                   CameraPath::Motion motion = CameraPath::Motion::still, uint32_t width = 320,
                                   uint32_t height = 180) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = motion;
    settings.sinks = {"shadow.sun"};
    settings.params = std::move(params);
    Renderer renderer(*gpu_, scene, settings);
    std::vector<Frame> frames;
    for (uint32_t i = 0; i < count; ++i) {
      const RenderedFrame rendered = renderer.render_frame(i, true);
      Frame f;
      f.non_finite = first_non_finite(rendered.execution);
      f.plan = recorded_pass(rendered, "shadow.distant_plan");
      f.levels = recorded_pass(rendered, "shadow.distant");
      f.resolve = recorded_pass(rendered, "shadow.sun_resolve");
      for (size_t p = 0; p < rendered.graph.passes.size(); ++p) {
        const std::string& name = rendered.graph.passes[p].decl->name;
        if (name == "shadow.distant_plan") f.planned = rendered.graph.passes[p].runs;
        if (name == "shadow.distant") f.ran = rendered.graph.passes[p].runs;
      }
      if (f.plan.outputs.count("shadow.distant_plan") &&
          f.plan.outputs.at("shadow.distant_plan").bytes->size() == sizeof(DistantPlan)) {
        std::memcpy(&f.decision, f.plan.outputs.at("shadow.distant_plan").bytes->data(), sizeof(DistantPlan));
        std::memcpy(&f.data, f.plan.outputs.at("shadow.distant_data").bytes->data(), sizeof(GpuDistantLevels));
      }
      if (f.plan.inputs.count("frame.camera")) {
        const CameraRecordGpu camera =
            host_records<CameraRecordGpu>(std::span<const uint8_t>(*f.plan.inputs.at("frame.camera").bytes)).at(0);
        f.eye = dvec3(camera.world[12], camera.world[13], camera.world[14]);
      }
      frames.push_back(std::move(f));
    }
    return frames;
  }

  static const std::vector<uint8_t>& levels_of(const Frame& f) { return *f.levels.outputs.at("shadow.distant").bytes; }

  // Each distant pass (and the resolve) run again on the inputs the frame recorded writes the same bytes.
  static void expect_replays(const Frame& f, const std::map<std::string, ParamValues>& params) {
    for (const auto& [decl, r] :
         {std::pair{shadow_distant_plan_pass(), &f.plan}, std::pair{shadow_distant_pass(), &f.levels},
          std::pair{shadow_sun_resolve_pass(), &f.resolve}}) {
      if (r->outputs.empty()) continue;
      const auto it = params.find(decl.name);
      const IsolatedRun again = run(decl, r->inputs, 320, 180, it == params.end() ? ParamValues{} : it->second);
      for (const auto& [name, output] : r->outputs)
        EXPECT_TRUE(*again.outputs.at(name) == *output.bytes) << decl.name << ": " << name << " differs when run again";
    }
  }
};

// The level sun_resolve.comp reads at camera-relative p (the finest that holds its filter), or -1.
int level_at(const GpuDistantLevels& d, const dvec3& p) {
  const double reach = 2.0 * (1 + 2) / d.light_direction.w;
  for (int k = 0; k < int(kDistantLevels); ++k) {
    const glm::dvec4 clip = glm::dmat4(d.light_from_world[k]) * glm::dvec4(p, 1.0);
    if (std::abs(clip.x) <= 1.0 - reach && std::abs(clip.y) <= 1.0 - reach) return k;
  }
  return -1;
}

TEST_F(DistantShadows, BeyondTheCascadesAgreeWithARayCast) {
  const Scene scene = field_scene(kSun);
  const Frame f = render(scene, 1, distant_params(1e9), CameraPath::Motion::still, 640, 360).at(0);
  EXPECT_EQ(f.non_finite, "");
  ASSERT_TRUE(f.ran && !f.resolve.outputs.empty());
  EXPECT_EQ(f.decision.reset, uint32_t(DistantReset::no_history)) << "frame 0 draws every level at once";
  EXPECT_EQ(f.decision.pending, 0u);
  const ShadowView v(f.resolve.inputs, f.resolve.outputs.at("shadow.sun"));
  const ShadowTriangles triangles(scene, f.eye);
  const dvec3 l = v.to_sun();
  size_t compared = 0, agreed = 0, shadowed = 0, near_edge = 0;
  size_t per_level[kDistantLevels] = {};
  std::string first;
  for (uint32_t y = 1; y < v.height; y += 3)
    for (uint32_t x = 1; x < v.width; x += 3) {
      const auto s = v.surface(x, y);
      if (!s || s->view_depth <= v.cascades.splits[3] || glm::dot(s->normal, l) <= 0.1) continue;
      const int level = level_at(f.data, s->position);
      ASSERT_GE(level, 0) << "the last level covers the whole map";
      const bool lit = triangles.lit(s->position, s->normal, l, s->view_depth);
      const double texel = f.data.texel_metres[level];
      const dvec3 u =
          glm::normalize(glm::cross(s->normal, std::abs(s->normal.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0)));
      const dvec3 w2 = glm::cross(s->normal, u);
      bool edge = false;
      for (int k = 0; k < 8 && !edge; ++k) {
        const double angle = k * 0.7853981633974483;
        const dvec3 w = u * std::cos(angle) + w2 * std::sin(angle);
        const double across = glm::length(w - glm::dot(w, l) * l);
        edge =
            triangles.lit(s->position + w * (2.0 * texel / std::max(across, 0.1)), s->normal, l, s->view_depth) != lit;
      }
      if (edge) {
        ++near_edge;
        continue;
      }
      const bool agrees = (v.visibility(x, y) >= 0.5) == lit;
      ++compared;
      ++per_level[level];
      shadowed += !lit;
      agreed += agrees;
      if (!agrees && first.empty())
        first = "pixel " + std::to_string(x) + "," + std::to_string(y) + " (level " + std::to_string(level) +
                "): ray cast " + (lit ? "lit" : "shadowed") + ", visibility " + std::to_string(v.visibility(x, y));
    }
  std::printf(
      "beyond the cascades: %zu of %zu sampled pixels agree (%.3f%%; %zu ray-shadowed; levels 0-3: %zu %zu %zu %zu), "
      "%zu near an edge; texels %.3f %.3f %.3f %.3f m\n",
      agreed, compared, compared ? 100.0 * agreed / compared : 0.0, shadowed, per_level[0], per_level[1], per_level[2],
      per_level[3], near_edge, f.data.texel_metres[0], f.data.texel_metres[1], f.data.texel_metres[2],
      f.data.texel_metres[3]);
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(shadowed, 100u) << "the test needs shadows to compare";
  EXPECT_GT(per_level[0], 100u);
  EXPECT_GT(per_level[1], 20u) << "the test should reach a coarser level";
  EXPECT_GE(double(agreed), 0.99 * double(compared)) << first;
}

// The camera jumps 55 m without a cut, past a snap step of levels 0–2: the plan, reading its
// record of the view before, marks stale exactly the tiles that now cover texels no complete
// tile covered, redraws them finest first within the budget over the next frames (each run of
// the plan and of shadow.distant on the previous one's outputs, as the renderer chains them),
// never redraws a complete tile, and ends with levels that agree with a full render there: bit
// for bit in the redrawn tiles, to the moved-level tolerance (AMovedLevelKeepsWhatItCovered) in
// the kept ones.
TEST_F(DistantShadows, StaleTilesAreRedrawnWithinTheBudgetUntilTheLevelsAreWhole) {
  const Scene scene = field_scene(kSun);
  Scene there = scene;
  there.camera->world[3] += glm::dvec4(37.0, 0.0, -41.0, 0.0);
  const double budget = 30;  // a box is 12 triangles: two or three units a frame
  const Frame here = render(scene, 1, distant_params(budget)).at(0);
  const Frame full = render(there, 1, distant_params(1e9)).at(0);
  ASSERT_TRUE(here.ran && full.ran);
  EXPECT_EQ(here.decision.reset, uint32_t(DistantReset::no_history));
  for (uint32_t k = 0; k < kDistantLevels; ++k) EXPECT_EQ(here.decision.complete[k], 0xfu) << "level " << k;
  const uint32_t tiles = here.decision.tiles_per_side, n = here.decision.resolution, side = n / tiles;

  std::map<std::string, IsolatedInput> plan_inputs = full.plan.inputs;
  plan_inputs[previous("shadow.distant_plan")] = here.plan.outputs.at("shadow.distant_plan");
  std::map<std::string, IsolatedInput> level_inputs = full.levels.inputs;
  level_inputs[previous("shadow.distant")] = here.levels.outputs.at("shadow.distant");
  const ParamValues plan_params{{"level0_metres", 128.0}, {"budget_triangles", budget}, {"tiles", 2.0}};
  DistantPlan before = here.decision;
  uint32_t frames = 0, stale_at_first = 0;
  uint32_t ever_stale[kDistantLevels] = {};
  std::vector<uint8_t> levels;
  for (; frames < 20; ++frames) {
    const IsolatedRun planned = run(shadow_distant_plan_pass(), plan_inputs, 320, 180, plan_params);
    DistantPlan p{};
    ASSERT_EQ(planned.outputs.at("shadow.distant_plan")->size(), sizeof(p));
    std::memcpy(&p, planned.outputs.at("shadow.distant_plan")->data(), sizeof(p));
    GpuDistantLevels data{};
    std::memcpy(&data, planned.outputs.at("shadow.distant_data")->data(), sizeof(data));
    EXPECT_EQ(p.reset, uint32_t(DistantReset::none));
    uint32_t stale = 0, redrawn = 0;
    for (uint32_t k = 0; k < kDistantLevels; ++k) {
      const glm::ivec2 shift(data.refresh[k].x, data.refresh[k].y);
      EXPECT_EQ(shift, glm::ivec2(p.centre[2 * k], p.centre[2 * k + 1]) -
                           glm::ivec2(before.centre[2 * k], before.centre[2 * k + 1]));
      // The expected stale tiles, texel by texel: a texel whose previous place was outside the
      // level or in a tile that was not complete.
      uint32_t want = 0;
      for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
          const glm::ivec2 from = glm::ivec2(x, y) + shift;
          const bool kept = from.x >= 0 && from.y >= 0 && from.x < int(n) && from.y < int(n) &&
                            (before.complete[k] >> (from.y / side * tiles + from.x / side) & 1u);
          if (!kept) want |= 1u << (y / side * tiles + x / side);
        }
      EXPECT_EQ(p.stale[k], want) << "frame " << frames << ", level " << k;
      EXPECT_EQ(p.refreshed[k] & ~p.stale[k], 0u) << "a complete tile redrawn";
      EXPECT_EQ(p.complete[k], (0xfu & ~p.stale[k]) | p.refreshed[k]);
      ever_stale[k] |= p.stale[k];
      stale += std::popcount(p.stale[k]);
      redrawn += std::popcount(p.refreshed[k]);
    }
    if (frames == 0) stale_at_first = stale;
    EXPECT_TRUE(p.triangles <= budget || (p.over_budget && redrawn == 1)) << "frame " << frames;
    EXPECT_EQ(p.pending, stale - redrawn);
    EXPECT_GT(redrawn, 0u) << "a stale unit waits while nothing is drawn";

    std::map<std::string, IsolatedInput> inputs = level_inputs;
    for (const char* name : {"shadow.distant_plan", "shadow.distant_data", "draws.shadow.distant"})
      inputs[name] = {planned.output_descs.at(name), planned.outputs.at(name)};
    const IsolatedRun drawn = run(shadow_distant_pass(), inputs, 320, 180);
    levels = *drawn.outputs.at("shadow.distant");
    plan_inputs[previous("shadow.distant_plan")] = {planned.output_descs.at("shadow.distant_plan"),
                                                    planned.outputs.at("shadow.distant_plan")};
    level_inputs[previous("shadow.distant")].bytes = drawn.outputs.at("shadow.distant");
    before = p;
    if (p.pending == 0) break;
  }
  std::printf("a 55 m jump: %u stale units, redrawn over %u frames within %.0f triangles each\n", stale_at_first,
              frames + 1, budget);
  EXPECT_GT(stale_at_first, 3u) << "the jump should leave several tiles stale";
  EXPECT_GT(frames, 1u) << "the budget should spread the refresh";
  ASSERT_EQ(before.pending, 0u) << "the levels never became whole";
  // Kept tiles hold depths rasterised at the view before (camera-relative floats): a quarter
  // texel of depth at most, a silhouette texel in a thousand may flip.
  const auto& want = levels_of(full);
  size_t apart = 0, compared = 0, redrawn_differ = 0;
  for (uint32_t k = 0; k < kDistantLevels; ++k)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const size_t at = ((size_t(k) * n + y) * n + x) * 4;
        float a, b;
        std::memcpy(&a, &levels[at], 4);
        std::memcpy(&b, &want[at], 4);
        if (ever_stale[k] >> (y / side * tiles + x / side) & 1u) {
          redrawn_differ += a != b;
          continue;
        }
        ++compared;
        if (std::abs(double(a) - double(b)) * full.data.depth_metres[k] / full.data.texel_metres[k] > 0.25) ++apart;
      }
  EXPECT_EQ(redrawn_differ, 0u) << "a redrawn tile is the full render's";
  EXPECT_LE(double(apart), 1e-3 * double(compared));
}

TEST_F(DistantShadows, UpToDateLevelsAreCarriedNotDrawn) {
  const Scene scene = field_scene(kSun);
  const std::vector<Frame> frames = render(scene, 6, distant_params(30));
  const size_t layer = levels_of(frames[0]).size() / kDistantLevels;
  size_t carried = 0;
  for (size_t i = 1; i < frames.size(); ++i)
    for (uint32_t k = 0; k < kDistantLevels; ++k) {
      if (frames[i].decision.refreshed[k] != 0) continue;
      ++carried;
      for (uint32_t u = 0; u < 4; ++u) EXPECT_EQ(frames[i].decision.unit_draws[k * 4 + u], 0u);
      EXPECT_TRUE(std::equal(levels_of(frames[i]).begin() + k * layer, levels_of(frames[i]).begin() + (k + 1) * layer,
                             levels_of(frames[i - 1]).begin() + k * layer))
          << "frame " << i << ", level " << k << " changed without a redraw";
    }
  EXPECT_EQ(carried, (frames.size() - 1) * kDistantLevels) << "a still camera redraws nothing after frame 0";
  // With the cache off every level is drawn whole each frame.
  auto off = distant_params(30);
  off["shadow.distant_plan"]["cache"] = 0.0;
  const std::vector<Frame> uncached = render(scene, 2, off);
  EXPECT_EQ(uncached[1].decision.reset, uint32_t(DistantReset::cache_off));
  for (uint32_t k = 0; k < kDistantLevels; ++k) EXPECT_EQ(uncached[1].decision.refreshed[k], 0xfu);
  EXPECT_TRUE(levels_of(uncached[1]) == levels_of(frames[1]));
  // The sun below the horizon: neither pass runs.
  const Frame night = render(with_sun(scene, {0.3f, 0.5f, 0.2f}), 1, distant_params(30)).at(0);
  EXPECT_FALSE(night.ran);
  EXPECT_FALSE(night.planned);
}

// The camera moves 40 m, more than a snap step of levels 0–2 (16, 64, 256 m): the kept texels
// (those not redrawn, covered before) are the full render's at the new view.
TEST_F(DistantShadows, AMovedLevelKeepsWhatItCovered) {
  const Scene scene = field_scene(kSun);
  Scene there = scene;
  there.camera->world[3] += glm::dvec4(37.0, 0.0, -41.0, 0.0);
  const auto frames_here = render(scene, 1, distant_params(1e9)).at(0);
  const auto full_there = render(there, 1, distant_params(1e9)).at(0);
  ASSERT_TRUE(frames_here.ran && full_there.ran);
  // The history of `here` read at `there`: run shadow.distant on `there`'s plan with nothing due.
  std::map<std::string, IsolatedInput> inputs = full_there.levels.inputs;
  inputs[previous("shadow.distant")] = frames_here.levels.outputs.at("shadow.distant");
  GpuDistantLevels data = full_there.data;
  DistantPlan plan = full_there.decision;
  const dvec3 shift_metres = dvec3(37.0, 0.0, -41.0);
  const double resolution = data.light_direction.w;
  glm::ivec2 shifts[kDistantLevels];
  for (uint32_t k = 0; k < kDistantLevels; ++k) {
    // The planner's own shift, recomputed as it would be with `here` as the previous view.
    // One world point, `here`'s eye: at the origin of `here`'s camera-relative space.
    const glm::dvec4 now = glm::dmat4(frames_here.data.light_from_world[k]) * glm::dvec4(0.0, 0.0, 0.0, 1.0);
    const glm::dvec4 then = glm::dmat4(full_there.data.light_from_world[k]) * glm::dvec4(-shift_metres, 1.0);
    shifts[k] = glm::ivec2(glm::round((glm::dvec2(now) - glm::dvec2(then)) * 0.5 * resolution));
    data.refresh[k] = glm::ivec4(shifts[k], 0, int(plan.tiles_per_side));
    plan.refreshed[k] = 0;
  }
  EXPECT_NE(shifts[0], glm::ivec2(0)) << "level 0 should move";
  EXPECT_EQ(shifts[3], glm::ivec2(0)) << "the last level stays on the map";
  auto bytes = [](const auto& value) {
    return std::make_shared<std::vector<uint8_t>>(reinterpret_cast<const uint8_t*>(&value),
                                                  reinterpret_cast<const uint8_t*>(&value) + sizeof(value));
  };
  inputs["shadow.distant_data"].bytes = bytes(data);
  inputs["shadow.distant_plan"].bytes = bytes(plan);
  const IsolatedRun kept = run(shadow_distant_pass(), inputs, 320, 180);
  const auto& got = *kept.outputs.at("shadow.distant");
  const auto& want = levels_of(full_there);
  const uint32_t n = uint32_t(resolution);
  // Camera-relative float positions, and the rasterizer's sub-texel snapping of them, differ at the
  // two views: depths match to a small part of a texel's side (far below the resolve's half-texel
  // bias), and a texel on a caster's silhouette may flip.
  size_t compared = 0, bits = 0, apart = 0;
  double largest = 0.0;
  for (uint32_t k = 0; k < kDistantLevels; ++k)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const glm::ivec2 before = glm::ivec2(x, y) + shifts[k];
        if (before.x < 0 || before.y < 0 || before.x >= int(n) || before.y >= int(n)) continue;
        const size_t at = ((size_t(k) * n + y) * n + x) * 4;
        float a, b;
        std::memcpy(&a, &got[at], 4);
        std::memcpy(&b, &want[at], 4);
        ++compared;
        bits += a != b;
        const double texels = std::abs(double(a) - double(b)) * data.depth_metres[k] / data.texel_metres[k];
        if (texels > 0.25)
          ++apart;
        else
          largest = std::max(largest, texels);
      }
  std::printf(
      "moved: %zu kept texels, %zu not bit-identical to a full render there, %zu more than 1/4 texel of depth "
      "apart, the rest within %.4f texel (shifts %d,%d %d,%d %d,%d)\n",
      compared, bits, apart, largest, shifts[0].x, shifts[0].y, shifts[1].x, shifts[1].y, shifts[2].x, shifts[2].y);
  EXPECT_GT(compared, size_t(n) * n * 2);
  EXPECT_LE(double(apart), 1e-3 * double(compared));
  EXPECT_LE(largest, 0.1);
}

TEST_F(DistantShadows, AFrameOfADrivingCameraReplays) {
  Scene map = build_map({1, 2.0, Shot::street});
  add_default_lighting(map);
  const auto params = std::map<std::string, ParamValues>{{"shadow.distant_plan", {{"budget_triangles", 20000}}}};
  const std::vector<Frame> frames = render(map, 3, params, CameraPath::Motion::drive);
  for (const Frame& f : frames) {
    EXPECT_EQ(f.non_finite, "");
    EXPECT_TRUE(f.ran);
    std::printf("2 km map, driving: reset %u, %u draws, %u triangles, %u units pending, levels %x %x %x %x\n",
                f.decision.reset, f.decision.draws, f.decision.triangles, f.decision.pending, f.decision.refreshed[0],
                f.decision.refreshed[1], f.decision.refreshed[2], f.decision.refreshed[3]);
  }
  ASSERT_TRUE(frames[2].plan.inputs.count(previous("shadow.distant_plan")));
  EXPECT_TRUE(*frames[2].plan.inputs.at(previous("shadow.distant_plan")).bytes ==
              *frames[1].plan.outputs.at("shadow.distant_plan").bytes)
      << "frame 2's plan reads frame 1's";
  ASSERT_TRUE(frames[2].levels.inputs.count(previous("shadow.distant")));
  EXPECT_TRUE(*frames[2].levels.inputs.at(previous("shadow.distant")).bytes == levels_of(frames[1]))
      << "frame 2 reads frame 1's levels";
  expect_replays(frames[2], params);
}

TEST_F(DistantShadows, StressStaysFiniteAndReplays) {
  const Scene field = field_scene(kSun);
  const std::vector<std::pair<const char*, Scene>> cases = {
      {"sun at the horizon", with_sun(field, {1.0f, -1e-3f, 0.3f})},
      {"sun straight down", with_sun(field, {0.0f, -1.0f, 0.0f})},
      {"map's far corner", [] {
         Scene s = build_map({1, 1.0, Shot::street});
         add_default_lighting(s);
         for (Instance& instance : s.instances) instance.world[3] += glm::dvec4(7500.0, 0.0, 7500.0, 0.0);
         for (Light& light : s.lights) light.position += dvec3(7500.0, 0.0, 7500.0);
         if (s.camera) s.camera->world[3] += glm::dvec4(7500.0, 0.0, 7500.0, 0.0);
         return s;
       }()}};
  const auto params = distant_params(60);
  for (const auto& [name, scene] : cases) {
    SCOPED_TRACE(name);
    const std::vector<Frame> frames = render(scene, 2, params);
    for (const Frame& f : frames) {
      EXPECT_EQ(f.non_finite, "");
      ASSERT_TRUE(f.ran);
      for (uint32_t k = 0; k < kDistantLevels; ++k)
        for (int c = 0; c < 16; ++c) EXPECT_TRUE(std::isfinite((&f.data.light_from_world[k][0][0])[c]));
    }
    expect_replays(frames[1], params);
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
