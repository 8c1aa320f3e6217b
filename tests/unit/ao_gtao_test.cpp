// ao.gtao against analytic cases, on half-resolution inputs ray-cast on the CPU from planes (each
// half texel's depth and normal where the ray through its footprint's centre meets the scene, as
// the pass places it), at the default parameters, noise included:
// - an open plane (a street seen from 1.7 m, looking 20° down) is unoccluded: visibility 1, and
//   the bent normal is the plane's normal (within 1° on average, 5° at most);
// - a 90° crease (the street meeting a wall): a point of the street at the wall's foot sees half
//   its cosine-weighted hemisphere, visibility 0.5; within 1% of the radius from the wall the
//   finite radius frees at most the 1.6% of that hemisphere whose rays reach the wall beyond
//   the falloff's start (so 0.508 ± 0.008). The radius is 20 m and the search may reach 512
//   pixels: the wall must be near against the radius, and on screen. The mean bent normal is
//   within 5° on average (15° at most) of the half hemisphere's mean direction;
// - a sphere of radius r over the street hides (r/D)²·cos α of a street point's cosine-weighted
//   hemisphere, D being the distance to its centre and α its angle from the normal ((r/d)² below
//   its centre, d its height), with the slabs as deep as r: with everything behind a surface
//   solid the sphere would hide all that lies behind it. The radius and falloff keep the whole
//   sphere at full weight; 16 slices × 32 steps, 640×360;
// - the sky and bad depths: visibility exactly 1 (code 255) where nothing was drawn and where the
//   depth is NaN, 0 or 65504, with everything behind a surface solid and with slabs 0.5 m deep.
// Bound (accuracy.md): over the texels of each case, mean |error| ≤ 0.02 and the largest ≤ 0.08.
#include <cmath>
#include <cstring>
#include <optional>

#include "passes/ao/kinds.h"
#include "passes/ao/stage.h"
#include "passes/core/format.h"
#include "passes/depth/kinds.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/view.h"
#include "passes/normals/kinds.h"
#include "tests/unit/ao_synthetic.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

class AoGtao : public GpuTest {
 protected:
  // ao.raw of frame `frame` (the noise moves with it).
  static std::vector<uint8_t> resolve(const Synthetic& s, ParamValues params, uint32_t frame) {
    GpuFrameConstants constants{};
    constants.counts.y = frame;
    const IsolatedRun result =
        run(ao_gtao_pass(),
            {{"frame.views", record_input(s.view)},
             {"frame.constants", record_input(constants)},
             {"depth.half", image(VK_FORMAT_R16_SFLOAT, kinds::linear_depth, s.half_width(), s.half_height(), s.depth)},
             {"normals.half",
              image(VK_FORMAT_R8G8B8A8_UNORM, kinds::packed_normal, s.half_width(), s.half_height(), s.normals)}},
            s.width, s.height, params);
    return *result.outputs.at("ao.raw");
  }
  // Each texel's visibility and bent normal averaged over frames 0..7, what ao.temporal
  // accumulates for a still view: each frame's slices and steps are another sample of the noise.
  struct Mean {
    std::vector<double> visibility;
    std::vector<glm::dvec3> bent;
  };
  static Mean mean_of_frames(const Synthetic& s, const ParamValues& params) {
    Mean mean{std::vector<double>(s.hits.size(), 0.0), std::vector<glm::dvec3>(s.hits.size(), glm::dvec3(0.0))};
    for (uint32_t frame = 0; frame < 8; ++frame) {
      const std::vector<uint8_t> out = resolve(s, params, frame);
      for (size_t i = 0; i < s.hits.size(); ++i) {
        mean.visibility[i] += out[i * 4 + 3] / 255.0 / 8;
        mean.bent[i] += glm::dvec3(out[i * 4], out[i * 4 + 1], out[i * 4 + 2]) / 127.5 - 1.0;
      }
    }
    return mean;
  }
};

// ao.gtao's two pipelines: everything behind a surface solid (the default), and slabs.
constexpr double kSolidAndSlabs[] = {0.0, 0.5};

struct Errors {
  double sum = 0, worst = 0;
  size_t count = 0;
  void add(double error) {
    sum += std::abs(error);
    worst = std::max(worst, std::abs(error));
    ++count;
  }
  double mean() const { return count ? sum / count : 0; }
};

TEST_F(AoGtao, AnOpenPlaneIsUnoccluded) {
  const Synthetic s = cast(320, 180, {0, 1.7, 0}, {0, -std::tan(glm::radians(20.0)), -1}, {{{0, 1, 0}, 0.0}});
  const Mean mean = mean_of_frames(s, {});
  const std::vector<uint8_t> out = resolve(s, {}, 0);
  Errors visibility, one_frame, bend;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    if (!s.hits[i]) continue;
    visibility.add(mean.visibility[i] - 1.0);
    one_frame.add(out[i * 4 + 3] / 255.0 - 1.0);
    bend.add(glm::degrees(std::acos(std::min(1.0, glm::normalize(mean.bent[i]).y))));
  }
  std::printf(
      "open plane: %zu texels: 8 frames' mean visibility, mean |error| %.4f, largest %.4f (one frame "
      "%.4f, %.4f); their mean bent normal within %.2f° of the plane's on average, %.2f° at most\n",
      visibility.count, visibility.mean(), visibility.worst, one_frame.mean(), one_frame.worst, bend.mean(),
      bend.worst);
  ASSERT_GT(visibility.count, 1000u);
  EXPECT_LE(visibility.mean(), 0.02);
  EXPECT_LE(visibility.worst, 0.08);
  // The 8-bit normal's codes tilt it 0.32° (all there is now: samples on their texel's plane leave
  // the plane unoccluded to the code; at texel centres, off the slice, they reached 4.5°).
  EXPECT_LE(bend.mean(), 1.0);
  EXPECT_LE(bend.worst, 5.0);
}

TEST_F(AoGtao, APointAtTheFootOfAWallSeesHalfItsHemisphere) {
  // The street (y = 0) meets a wall (x = -2, facing +x); the camera looks along the wall's foot.
  const Synthetic s = cast(320, 180, {0, 1.7, 0}, {-0.3, -0.25, -1}, {{{0, 1, 0}, 0.0}, {{1, 0, 0}, -2.0}});
  const double radius = 20.0;
  const ParamValues params = {{"radius", radius}, {"max_pixels", 512.0}, {"slices", 16}, {"steps", 32}};
  const Mean mean = mean_of_frames(s, params);
  const std::vector<uint8_t> out = resolve(s, params, 0);
  Errors visibility, one_frame, bend;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    if (!s.hits[i] || s.hits[i]->y > 1e-6) continue;
    // Nearer the wall than depth.half resolves (2 half ULPs of the depth, 2⁻⁹ of it), the point may
    // land behind the wall; where a half pixel spans more than 1% of the radius, the crease is
    // below the image's resolution.
    const double from_wall = s.hits[i]->x + 2.0, depth = -s.hits[i]->z;
    if (from_wall < depth * 0x1p-9 || from_wall > 0.01 * radius || depth > 20.0) continue;
    // 0.5, up to 0.016 more: the nearest analytic value is 0.5 + 0.008.
    visibility.add(mean.visibility[i] - 0.508);
    // The cosine-weighted mean direction of the half hemisphere away from the wall: 4/(3π) out of
    // it, 2/3 up.
    bend.add(glm::degrees(std::acos(std::min(
        1.0, glm::dot(glm::normalize(mean.bent[i]), glm::normalize(glm::dvec3(4 / (3 * M_PI), 2.0 / 3, 0)))))));
    one_frame.add(out[i * 4 + 3] / 255.0 - 0.508);
  }
  std::printf(
      "crease: %zu street texels within 1%% of the radius from the wall: 8 frames' mean visibility, mean "
      "|error| %.4f, largest %.4f (one frame %.4f, %.4f); their mean bent normal %.2f° from the half "
      "hemisphere's mean direction on average, %.2f° at most\n",
      visibility.count, visibility.mean(), visibility.worst, one_frame.mean(), one_frame.worst, bend.mean(),
      bend.worst);
  ASSERT_GT(visibility.count, 20u);
  EXPECT_LE(visibility.mean(), 0.02);
  EXPECT_LE(visibility.worst, 0.08);
  EXPECT_LE(bend.mean(), 5.0);
  EXPECT_LE(bend.worst, 15.0);
}

TEST_F(AoGtao, ASphereOverAPatchHidesTheCosineWeightedSolidAngleItSubtends) {
  // A sphere of radius r, its centre d above the street, seen from 3 m up and 4 m away.
  const double r = 0.4, d = 1.0;
  const glm::dvec3 centre(0, d, -4);
  const Synthetic s = cast(640, 360, {0, 3, 0}, {0, -3, -4}, {{{0, 1, 0}, 0.0}}, {{centre, r}});
  // The sphere's farthest point is 1.52 m from a point within d/2 of the one below its centre,
  // under the 2.475 m where the weight starts to fall.
  const ParamValues params = {{"radius", 2.5}, {"falloff", 0.01}, {"thickness", r}, {"slices", 16}, {"steps", 32}};
  const Mean mean = mean_of_frames(s, params);
  Errors visibility;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    if (!s.hits[i] || s.hits[i]->y > 1e-6) continue;
    const glm::dvec3 to_centre = centre - *s.hits[i];
    if (glm::length(glm::dvec2(to_centre.x, to_centre.z)) > 0.5 * d) continue;
    const double distance = glm::length(to_centre);
    visibility.add(mean.visibility[i] - (1 - r * r / (distance * distance) * (to_centre.y / distance)));
  }
  std::printf(
      "sphere over a patch: %zu street texels within d/2 of the point below its centre (there 1 - (r/d)^2 = "
      "%.2f): 8 frames' mean visibility, mean |error| %.4f, largest %.4f\n",
      visibility.count, 1 - r * r / (d * d), visibility.mean(), visibility.worst);
  ASSERT_GT(visibility.count, 100u);
  EXPECT_LE(visibility.mean(), 0.02);
  EXPECT_LE(visibility.worst, 0.08);
}

TEST_F(AoGtao, NothingDrawnAndNonFiniteDepthsOccludeNothing) {
  Synthetic s = cast(64, 36, {0, 1.7, 0}, {0, -0.4, -1}, {{{0, 1, 0}, 0.0}});
  // Half row 12: NaN, 0 and 65504 depths on the street.
  const uint16_t bad[] = {0x7e00, 0x0000, 0x7bff};
  for (uint32_t x = 0; x < s.half_width(); ++x) {
    const size_t i = size_t(12) * s.half_width() + x;
    std::memcpy(s.depth.data() + i * 2, &bad[x % 3], 2);
  }
  for (const double thickness : kSolidAndSlabs) {
    const std::vector<uint8_t> out = resolve(s, {{"thickness", thickness}}, 0);
    for (size_t i = 0; i < s.hits.size(); ++i) {
      const bool row = i / s.half_width() == 12;
      if (s.hits[i] && !row) continue;
      EXPECT_EQ(out[i * 4 + 3], 255) << "thickness " << thickness << ", half texel " << i;
    }
    for (size_t i = 0; i < out.size(); i += 4) EXPECT_GT(out[i + 3], 0) << "thickness " << thickness << ", " << i / 4;
  }
}

// Stress: outputs of 1×1 and 7×5 of a street, and a wall 1 m away below eye level in front of one
// 1 km away (a depth discontinuity of 1 km): the far wall's samples lie beyond the near wall's
// radius and the other way round, so every texel stays unoccluded; every visibility is in
// [0, 1] by its format, so what is checked is that nothing is invented: at most 2% of occlusion
// (allowed at the near wall's edge); with everything behind a surface solid and with slabs.
TEST_F(AoGtao, TinyOutputsAndAKilometreDiscontinuityInventNoOcclusion) {
  for (const double thickness : kSolidAndSlabs) {
    const ParamValues params = {{"thickness", thickness}};
    for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{7u, 5u}}) {
      const Synthetic s = cast(width, height, {0, 1.7, 0}, {0, -1, -1}, {{{0, 1, 0}, 0.0}});
      const std::vector<uint8_t> out = resolve(s, params, 0);
      for (size_t i = 0; i < s.hits.size(); ++i)
        EXPECT_EQ(out[i * 4 + 3], 255) << "thickness " << thickness << ", " << width << "x" << height << " " << i;
    }
    // Looking ahead: below eye level a wall 1 m away, above it another 1 km away.
    const Synthetic s = cast(160, 90, {0, 1.7, 0}, {0, 0, -1}, {{{0, 0, 1}, -1.0, 1.7}, {{0, 0, 1}, -1000.0}});
    const std::vector<uint8_t> out = resolve(s, params, 0);
    size_t far = 0;
    for (size_t i = 0; i < s.hits.size(); ++i) {
      ASSERT_TRUE(s.hits[i]);
      far += s.hits[i]->z < -999.0;
      EXPECT_GE(out[i * 4 + 3], 250) << "thickness " << thickness << ", half texel " << i;
    }
    EXPECT_GT(far, 100u);
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
