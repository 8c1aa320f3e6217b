// ao.filter against a CPU reference of its definition (passes/ao/filter.cpp), computed in double
// from the same inputs: a street meeting a wall ray-cast at half resolution (ao_synthetic.h) and
// ao.raw of random visibilities and bent normals. Each neighbour in the (2·radius + 1)² window
// weighs clamp(1 − |n·(p' − p)| / (plane_tolerance · depth), 0, 1) · max(n·n', 0)^normal_power,
// p and p' the view-space points of the two texels' depths at their footprints' centres.
// Bound: the visibility within 1.5 codes of the reference (the 8-bit store rounds once, and
// float against double moves a weight by far less than a code); the bent normal within 1.5° (its
// codes are 0.45° apart).
// Also: no occlusion crosses a 1 km depth discontinuity, and the sky and NaN depths keep ao.raw.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/ao/kinds.h"
#include "passes/ao/stage.h"
#include "passes/depth/kinds.h"
#include "passes/normals/kinds.h"
#include "tests/unit/ao_synthetic.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// ao.raw: at each drawn texel a visibility in [0.2, 1] and a bent normal tilted up to ~35° from
// the surface's normal, random; the clear value (codes 128, visibility 1) elsewhere.
std::vector<uint8_t> random_raw(const Synthetic& s, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> visibility(0.2, 1.0), tilt(-0.35, 0.35);
  std::vector<uint8_t> raw;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    const glm::dvec3 normal = decoded(s.normals, i);
    if (!s.hits[i]) {
      raw.insert(raw.end(), {128, 128, 128, 255});
      continue;
    }
    const glm::dvec3 bent = glm::normalize(normal + glm::dvec3(tilt(random), tilt(random), tilt(random)));
    for (int c = 0; c < 3; ++c) raw.push_back(uint8_t(std::lround((bent[c] * 0.5 + 0.5) * 255)));
    raw.push_back(uint8_t(std::lround(visibility(random) * 255)));
  }
  return raw;
}

class AoFilter : public GpuTest {
 protected:
  static std::vector<uint8_t> filter(const Synthetic& s, const std::vector<uint8_t>& raw, ParamValues params = {}) {
    const IsolatedRun result =
        run(ao_filter_pass(),
            {{"frame.views", record_input(s.view)},
             {"ao.raw", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::ao_bent, s.half_width(), s.half_height(), raw)},
             {"depth.half", image(VK_FORMAT_R16_SFLOAT, kinds::linear_depth, s.half_width(), s.half_height(), s.depth)},
             {"normals.half",
              image(VK_FORMAT_R8G8B8A8_UNORM, kinds::packed_normal, s.half_width(), s.half_height(), s.normals)}},
            s.width, s.height, params);
    return *result.outputs.at("ao.filtered");
  }
};

double depth_of(const Synthetic& s, size_t texel) {
  uint16_t h;
  std::memcpy(&h, s.depth.data() + texel * 2, 2);
  return half_to_float(h);
}
bool drawn(double depth) { return depth > 0.0 && depth < 65504.0; }

// The view-space point of half texel (x, y) at its depth, the pass's view_point at its footprint's centre.
glm::dvec3 view_point(const Synthetic& s, uint32_t x, uint32_t y) {
  const double depth = depth_of(s, size_t(y) * s.half_width() + x);
  const double cx = (2.0 * x + std::min(2 * x + 1, s.width - 1) + 1) * 0.5;
  const double cy = (2.0 * y + std::min(2 * y + 1, s.height - 1) + 1) * 0.5;
  const glm::dmat4 projection(s.view.projection);
  const double ndc_x = cx / s.width * 2 - 1, ndc_y = cy / s.height * 2 - 1;
  return {depth * (ndc_x + projection[2][0]) / projection[0][0], depth * (ndc_y + projection[2][1]) / projection[1][1],
          -depth};
}

struct Filtered {
  double visibility;
  glm::dvec3 bent;
};

Filtered reference(const Synthetic& s, const std::vector<uint8_t>& raw, uint32_t x, uint32_t y, int radius,
                   double plane_tolerance, double normal_power) {
  const size_t centre = size_t(y) * s.half_width() + x;
  const glm::dvec3 normal = glm::normalize(decoded(s.normals, centre));
  const glm::dvec3 view_normal = glm::dmat3(glm::dmat4(s.view.view)) * normal;
  const glm::dvec3 point = view_point(s, x, y);
  double weights = 0, visibility = 0;
  glm::dvec3 bent(0.0);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int ax = int(x) + dx, ay = int(y) + dy;
      if (ax < 0 || ay < 0 || ax >= int(s.half_width()) || ay >= int(s.half_height())) continue;
      const size_t at = size_t(ay) * s.half_width() + ax;
      const glm::dvec3 other = decoded(s.normals, at);
      if (!drawn(depth_of(s, at)) || glm::dot(other, other) < 1e-4) continue;
      const double off_plane = std::abs(glm::dot(view_normal, view_point(s, ax, ay) - point));
      const double weight = std::clamp(1.0 - off_plane / (plane_tolerance * -point.z), 0.0, 1.0) *
                            std::pow(std::max(glm::dot(normal, glm::normalize(other)), 0.0), normal_power);
      weights += weight;
      visibility += weight * raw[at * 4 + 3] / 255.0;
      bent += weight * decoded(raw, at);
    }
  return {visibility / weights, glm::normalize(bent)};
}

TEST_F(AoFilter, MatchesItsDefinitionAtACrease) {
  const Synthetic s = cast(320, 180, {0, 1.7, 0}, {-0.3, -0.25, -1}, {{{0, 1, 0}, 0.0}, {{1, 0, 0}, -2.0}});
  const std::vector<uint8_t> raw = random_raw(s, 7);
  for (const auto& [radius, tolerance, power] : {std::tuple{2, 0.02, 8.0}, std::tuple{4, 0.1, 1.0}}) {
    const std::vector<uint8_t> out =
        filter(s, raw, {{"radius", radius}, {"plane_tolerance", tolerance}, {"normal_power", power}});
    double worst_codes = 0, worst_degrees = 0;
    size_t compared = 0;
    for (uint32_t y = 0; y < s.half_height(); ++y)
      for (uint32_t x = 0; x < s.half_width(); ++x) {
        const size_t i = size_t(y) * s.half_width() + x;
        if (!s.hits[i]) continue;
        const Filtered expected = reference(s, raw, x, y, radius, tolerance, power);
        worst_codes = std::max(worst_codes, std::abs(out[i * 4 + 3] - expected.visibility * 255));
        worst_degrees = std::max(worst_degrees, degrees_between(decoded(out, i), expected.bent));
        ++compared;
      }
    std::printf(
        "radius %d, tolerance %.2f, power %.0f: %zu texels, visibility within %.2f codes, bent normal within %.2f°\n",
        radius, tolerance, power, compared, worst_codes, worst_degrees);
    EXPECT_GT(compared, 10000u);
    EXPECT_LE(worst_codes, 1.5);
    EXPECT_LE(worst_degrees, 1.5);
  }
}

// A wall 1 m away below eye level in front of another 1 km away: ao.raw holds 0.2 on the near wall
// and 1 on the far one; nothing of either reaches the other.
TEST_F(AoFilter, NoOcclusionCrossesAKilometreDiscontinuity) {
  const Synthetic s = cast(160, 90, {0, 1.7, 0}, {0, 0, -1}, {{{0, 0, 1}, -1.0, 1.7}, {{0, 0, 1}, -1000.0}});
  std::vector<uint8_t> raw;
  size_t near = 0;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    const bool is_near = s.hits[i]->z > -2.0;
    near += is_near;
    raw.insert(raw.end(), {128, 128, 255, uint8_t(is_near ? 51 : 255)});
  }
  const std::vector<uint8_t> out = filter(s, raw, {{"radius", 4}});
  for (size_t i = 0; i < s.hits.size(); ++i) EXPECT_EQ(out[i * 4 + 3], raw[i * 4 + 3]) << "half texel " << i;
  EXPECT_GT(near, 100u);
  EXPECT_LT(near, s.hits.size() - 100);
}

// The sky, NaN, 0 and 65504 depths: ao.raw's value as it is; 1×1 and 7×5 outputs run.
TEST_F(AoFilter, TexelsWithNothingDrawnKeepTheirValue) {
  Synthetic s = cast(64, 36, {0, 1.7, 0}, {0, -0.4, -1}, {{{0, 1, 0}, 0.0}});
  const uint16_t bad[] = {0x7e00, 0x0000, 0x7bff};
  for (uint32_t x = 0; x < s.half_width(); ++x)
    std::memcpy(s.depth.data() + (size_t(12) * s.half_width() + x) * 2, &bad[x % 3], 2);
  const std::vector<uint8_t> raw = random_raw(s, 3);
  const std::vector<uint8_t> out = filter(s, raw);
  for (size_t i = 0; i < s.hits.size(); ++i) {
    if (s.hits[i] && i / s.half_width() != 12) continue;
    for (int c = 0; c < 4; ++c) EXPECT_EQ(out[i * 4 + c], raw[i * 4 + c]) << "half texel " << i;
  }
  for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{7u, 5u}}) {
    const Synthetic tiny = cast(width, height, {0, 1.7, 0}, {0, -1, -1}, {{{0, 1, 0}, 0.0}});
    const std::vector<uint8_t> tiny_raw = random_raw(tiny, 5);
    const std::vector<uint8_t> tiny_out = filter(tiny, tiny_raw, {{"radius", 2}});
    for (uint32_t y = 0; y < tiny.half_height(); ++y)
      for (uint32_t x = 0; x < tiny.half_width(); ++x) {
        const size_t i = size_t(y) * tiny.half_width() + x;
        const Filtered expected = reference(tiny, tiny_raw, x, y, 2, 0.02, 8.0);
        EXPECT_LE(std::abs(tiny_out[i * 4 + 3] - expected.visibility * 255), 1.5) << width << "x" << height << " " << i;
      }
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
