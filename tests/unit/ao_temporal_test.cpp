// ao.temporal against what its history means, on a street (or a wall) ray-cast at half resolution
// (ao_synthetic.h) with ao.filtered and the history given:
// - a still view: after frame n each texel holds the mean of its n visibilities (the history's
//   frames count n), and the bent normal the running normalised blend of its n bent normals;
// - a camera cut (the graph clears ao.history and depth.half@previous): the current frame as it is;
// - history rejected where depth.half a frame ago disagrees with where the point was, and where
//   motion.mask marks the footprint; kept where it agrees;
// - a camera moved sideways by one half texel: each texel blends the history of the texel its
//   surface came from (the next one to the right);
// - NaN depths, NaN and infinite histories, 1×1 and 7×5 outputs: finite, unoccluded where nothing
//   was drawn.
// Bound: the visibility within 1 code of the double-precision value (the 8-bit store rounds once;
// the history's halves add under 0.1 code), the bent normal within 1° (codes 0.45° apart).
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "passes/ao/kinds.h"
#include "passes/ao/stage.h"
#include "passes/core/history_name.h"
#include "passes/depth/kinds.h"
#include "passes/gbuffer/kinds.h"
#include "tests/unit/ao_synthetic.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// A history texel: the bent normal, its frames (its length) and the visibility, as halves.
void put_history(std::vector<uint8_t>& bytes, size_t texel, glm::dvec3 bent, double frames, double visibility) {
  const glm::dvec3 scaled = glm::normalize(bent) * frames;
  const uint16_t h[4] = {float_to_half(float(scaled.x)), float_to_half(float(scaled.y)), float_to_half(float(scaled.z)),
                         float_to_half(float(visibility))};
  std::memcpy(bytes.data() + texel * 8, h, 8);
}
glm::dvec4 history_at(const std::vector<uint8_t>& bytes, size_t texel) {
  uint16_t h[4];
  std::memcpy(h, bytes.data() + texel * 8, 8);
  return {half_to_float(h[0]), half_to_float(h[1]), half_to_float(h[2]), half_to_float(h[3])};
}

struct Frame {
  std::vector<uint8_t> filtered;        // ao.filtered
  std::vector<uint8_t> history;         // ao.history@previous (empty: cleared, a cut)
  std::vector<uint8_t> previous_depth;  // depth.half@previous (empty: cleared, the sky)
  glm::dvec2 motion{0.0};               // motion.half at every texel, uv units
  std::vector<uint8_t> mask;            // motion.mask, full size (empty: none)
};
struct Result {
  std::vector<uint8_t> bent, history;
};

class AoTemporal : public GpuTest {
 protected:
  static Result temporal(const Synthetic& s, const Frame& f, ParamValues params = {}) {
    const uint32_t hw = s.half_width(), hh = s.half_height();
    std::vector<uint8_t> sky(size_t(hw) * hh * 2);
    for (size_t i = 0; i < sky.size(); i += 2) std::memcpy(sky.data() + i, "\xff\x7b", 2);  // 65504
    std::vector<uint8_t> motion;
    const uint16_t m[2] = {float_to_half(float(f.motion.x)), float_to_half(float(f.motion.y))};
    for (size_t i = 0; i < size_t(hw) * hh; ++i) motion.insert(motion.end(), (const uint8_t*)m, (const uint8_t*)m + 4);
    const IsolatedRun result = run(
        ao_temporal_pass(),
        {{"frame.views", record_input(s.view)},
         {"ao.filtered", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::ao_bent, hw, hh, f.filtered)},
         {previous("ao.history"), image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::ao_history, hw, hh,
                                        f.history.empty() ? std::vector<uint8_t>(size_t(hw) * hh * 8, 0) : f.history)},
         {"depth.half", image(VK_FORMAT_R16_SFLOAT, kinds::linear_depth, hw, hh, s.depth)},
         {previous("depth.half"),
          image(VK_FORMAT_R16_SFLOAT, kinds::linear_depth, hw, hh, f.previous_depth.empty() ? sky : f.previous_depth)},
         {"motion.half", image(VK_FORMAT_R16G16_SFLOAT, kinds::motion, hw, hh, motion)},
         {"motion.mask", image(VK_FORMAT_R8_UINT, kinds::mask, s.width, s.height,
                               f.mask.empty() ? std::vector<uint8_t>(size_t(s.width) * s.height, 0) : f.mask)}},
        s.width, s.height, params);
    Result out{*result.outputs.at("ao.bent"), *result.outputs.at("ao.history")};
    for (size_t i = 0; i < out.history.size() / 8; ++i) {
      const glm::dvec4 h = history_at(out.history, i);
      EXPECT_TRUE(std::isfinite(h.x + h.y + h.z + h.w)) << "ao.history texel " << i;
    }
    return out;
  }

  // ao.filtered: a visibility in [0.2, 1] and a bent normal tilted up to ~35° from the surface's
  // normal at each drawn texel, random; codes 128 and visibility 1 elsewhere.
  static std::vector<uint8_t> random_filtered(const Synthetic& s, std::mt19937& random) {
    std::uniform_real_distribution<double> visibility(0.2, 1.0), tilt(-0.35, 0.35);
    std::vector<uint8_t> out;
    for (size_t i = 0; i < s.hits.size(); ++i) {
      if (!s.hits[i]) {
        out.insert(out.end(), {128, 128, 128, 255});
        continue;
      }
      const glm::dvec3 bent =
          glm::normalize(decoded(s.normals, i) + glm::dvec3(tilt(random), tilt(random), tilt(random)));
      for (int c = 0; c < 3; ++c) out.push_back(uint8_t(std::lround((bent[c] * 0.5 + 0.5) * 255)));
      out.push_back(uint8_t(std::lround(visibility(random) * 255)));
    }
    return out;
  }
};

const glm::dvec3 kEye{0, 1.7, 0};
Synthetic street(uint32_t width = 160, uint32_t height = 90) {
  return cast(width, height, kEye, {0, -0.4, -1}, {{{0, 1, 0}, 0.0}});
}

TEST_F(AoTemporal, AStillViewAveragesItsFrames) {
  const Synthetic s = street();
  std::mt19937 random(11);
  std::vector<double> mean(s.hits.size(), 0.0);
  std::vector<glm::dvec3> blend(s.hits.size(), glm::dvec3(0.0));
  Frame frame;
  frame.previous_depth = s.depth;
  double worst_codes = 0, worst_degrees = 0;
  for (int n = 1; n <= 8; ++n) {
    frame.filtered = random_filtered(s, random);
    const Result out = temporal(s, frame);
    for (size_t i = 0; i < s.hits.size(); ++i) {
      if (!s.hits[i]) {
        EXPECT_EQ(out.bent[i * 4 + 3], 255);
        EXPECT_EQ(glm::length(glm::dvec3(history_at(out.history, i))), 0.0);
        continue;
      }
      mean[i] += (frame.filtered[i * 4 + 3] / 255.0 - mean[i]) / n;
      const glm::dvec3 now = glm::normalize(decoded(frame.filtered, i));
      blend[i] = n == 1 ? now : glm::normalize(glm::mix(blend[i], now, 1.0 / n));
      worst_codes = std::max(worst_codes, std::abs(out.bent[i * 4 + 3] - mean[i] * 255));
      worst_degrees = std::max(worst_degrees, degrees_between(decoded(out.bent, i), blend[i]));
      EXPECT_NEAR(glm::length(glm::dvec3(history_at(out.history, i))), n, 0.02 * n) << "texel " << i;
    }
    frame.history = out.history;
  }
  std::printf("8 still frames: the mean visibility within %.2f codes, the bent normal within %.2f°\n", worst_codes,
              worst_degrees);
  EXPECT_LE(worst_codes, 1.0);
  EXPECT_LE(worst_degrees, 1.0);
}

// After a cut the graph clears both histories: the output is the current frame, code for code.
TEST_F(AoTemporal, ACameraCutStartsFromTheCurrentFrame) {
  const Synthetic s = street();
  std::mt19937 random(5);
  Frame frame;
  frame.filtered = random_filtered(s, random);
  const Result out = temporal(s, frame);
  for (size_t i = 0; i < s.hits.size(); ++i) {
    if (!s.hits[i]) continue;
    EXPECT_EQ(out.bent[i * 4 + 3], frame.filtered[i * 4 + 3]) << "texel " << i;
    EXPECT_LE(degrees_between(decoded(out.bent, i), decoded(frame.filtered, i)), 0.5) << "texel " << i;
    EXPECT_NEAR(glm::length(glm::dvec3(history_at(out.history, i))), 1.0, 0.01);
  }
}

// A history of 7 frames at visibility 0.2 and a current 1.0. Left third: depth.half a frame ago
// was 50% farther (another surface: rejected); middle third: motion.mask marks it (rejected);
// right third: agreeing (kept: 1/8 of the current frame).
TEST_F(AoTemporal, DisagreeingDepthAndTheMotionMaskRejectTheHistory) {
  const Synthetic s = street();
  const uint32_t hw = s.half_width();
  Frame frame;
  frame.history.assign(s.hits.size() * 8, 0);
  frame.previous_depth = s.depth;
  frame.mask.assign(size_t(s.width) * s.height, 0);
  for (size_t i = 0; i < s.hits.size(); ++i) {
    frame.filtered.insert(frame.filtered.end(), {128, 255, 128, 255});
    put_history(frame.history, i, {0, 1, 0}, 7.0, 0.2);
    const uint32_t x = i % hw;
    if (x < hw / 3) {
      uint16_t h;
      std::memcpy(&h, s.depth.data() + i * 2, 2);
      h = float_to_half(std::min(half_to_float(h) * 1.5f, 65504.0f));
      std::memcpy(frame.previous_depth.data() + i * 2, &h, 2);
    } else if (x < 2 * hw / 3) {
      frame.mask[size_t(i / hw) * 2 * s.width + 2 * x] = 1;  // one texel of the footprint
    }
  }
  const Result out = temporal(s, frame);
  size_t checked = 0;
  for (size_t i = 0; i < s.hits.size(); ++i) {
    const uint32_t x = i % hw;
    // Beyond 30 m the street's depth changes by over a third of itself from one texel to the next
    // (the grazing angle): the tolerance, which allows for that change, lets 50% pass.
    if (!s.hits[i] || -s.hits[i]->z > 30.0 || x == hw / 3 - 1 || x == hw / 3 || x == 2 * hw / 3 - 1 || x == 2 * hw / 3)
      continue;
    const double expected = x < 2 * hw / 3 ? 1.0 : 0.2 + (1.0 - 0.2) / 8;
    EXPECT_NEAR(out.bent[i * 4 + 3], expected * 255, 1.0) << "texel " << i << " (column " << x << ")";
    ++checked;
  }
  EXPECT_GT(checked, 1500u);
}

// Facing a wall 10 m away, the camera moved 1 half texel's width to the right since the last
// frame: the wall's points came from one half texel to the right.
TEST_F(AoTemporal, AMovedCameraTakesTheHistoryItsSurfaceCameFrom) {
  Synthetic s = cast(160, 90, kEye, {0, 0, -1}, {{{0, 0, 1}, -10.0}});
  const double metres = 4.0 * 10.0 / (s.width * double(s.view.projection[0][0]));
  const glm::dvec3 right(1, 0, 0);
  s.view.previous_view_projection =
      glm::mat4(glm::dmat4(s.view.view_projection) * glm::translate(glm::dmat4(1.0), -metres * right));
  const uint32_t hw = s.half_width();
  Frame frame;
  frame.motion = {-2.0 / s.width, 0.0};
  frame.previous_depth = s.depth;
  frame.history.assign(s.hits.size() * 8, 0);
  auto past = [](uint32_t x) { return 0.3 + 0.6 * (x % 7) / 6.0; };
  for (size_t i = 0; i < s.hits.size(); ++i) {
    frame.filtered.insert(frame.filtered.end(), {128, 128, 255, 128});
    put_history(frame.history, i, {0, 0, 1}, 3.0, past(i % hw));
  }
  const Result out = temporal(s, frame);
  for (size_t i = 0; i < s.hits.size(); ++i) {
    const uint32_t x = i % hw;
    const double now = 128 / 255.0;
    // The last column's surface came from outside the image: no history.
    const double expected = x + 1 < hw ? past(x + 1) + (now - past(x + 1)) / 4 : now;
    EXPECT_NEAR(out.bent[i * 4 + 3], expected * 255, 1.0) << "texel " << i << " (column " << x << ")";
  }
}

TEST_F(AoTemporal, NonFiniteInputsAndTinyOutputsStayFinite) {
  Synthetic s = street(64, 36);
  std::mt19937 random(2);
  Frame frame;
  frame.filtered = random_filtered(s, random);
  frame.previous_depth = s.depth;
  frame.history.assign(s.hits.size() * 8, 0);
  for (size_t i = 0; i < s.hits.size(); ++i) put_history(frame.history, i, {0, 1, 0}, 4.0, 0.5);
  const uint16_t nan = 0x7e00;
  for (uint32_t x = 0; x < s.half_width(); ++x) {
    std::memcpy(s.depth.data() + (size_t(12) * s.half_width() + x) * 2, &nan, 2);               // NaN now
    std::memcpy(frame.previous_depth.data() + (size_t(14) * s.half_width() + x) * 2, &nan, 2);  // NaN before
    const uint16_t nan4[4] = {nan, nan, nan, nan};
    std::memcpy(frame.history.data() + (size_t(16) * s.half_width() + x) * 8, nan4, 8);  // a NaN history
    const uint16_t inf4[4] = {0x7c00, 0x7c00, 0x7c00, 0x7c00};
    std::memcpy(frame.history.data() + (size_t(17) * s.half_width() + x) * 8, inf4, 8);  // an infinite one
  }
  const Result out = temporal(s, frame);
  for (uint32_t x = 0; x < s.half_width(); ++x) EXPECT_EQ(out.bent[(size_t(12) * s.half_width() + x) * 4 + 3], 255);
  for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{7u, 5u}}) {
    const Synthetic tiny = street(width, height);
    Frame f;
    f.filtered = random_filtered(tiny, random);
    f.previous_depth = tiny.depth;
    const Result first = temporal(tiny, f);
    f.history = first.history;
    const Result second = temporal(tiny, f);
    for (size_t i = 0; i < tiny.hits.size(); ++i) {
      if (!tiny.hits[i]) continue;
      EXPECT_EQ(second.bent[i * 4 + 3], f.filtered[i * 4 + 3]) << width << "x" << height << " " << i;
    }
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
