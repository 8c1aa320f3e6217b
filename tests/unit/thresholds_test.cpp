// Thresholds as data: the file's rules parsed strictly, and each per-texel metric on images built
// here whose answers are known by construction (a constant offset, a single firefly, a one-pixel
// shift, NaN on one side and on both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "compare/metrics.h"
#include "compare/thresholds.h"
#include "passes/gbuffer/kinds.h"
#include "tests/unit/image_record.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path file = fs::temp_directory_path() / ("nightcap-thresholds-" + std::to_string(getpid()) + "-" + name);
  std::ofstream(file) << text;
  return file;
}

FrameRecord frame(uint32_t width, uint32_t height) {
  FrameRecord f;
  f.width = width;
  f.height = height;
  return f;
}

ThresholdRule rule(TexelMetric metric, double limit, double allowed = 0.0, std::vector<IgnoreRect> ignore = {}) {
  ThresholdRule r;
  r.match = "*";
  r.metric = metric;
  r.limit = limit;
  r.allowed = allowed;
  r.ignore = std::move(ignore);
  return r;
}

TEST(Thresholds, FileRulesAndTheFirstMatchWins) {
  const fs::path file = write_file("good.json", R"({"thresholds": [
    {"match": "lighting.*/lighting.specular", "metric": "exact"},
    {"match": "lighting.*/*", "metric": "rel", "limit": 0.01, "allowed": 0.001,
     "ignore": [{"x": 0, "y": 0, "width": 64, "height": 32}]},
    {"match": "*", "metric": "abs", "limit": 0}]})");
  const Thresholds t = read_thresholds(file.string());
  ASSERT_EQ(t.rules.size(), 3u);
  ResourceRecord specular = image_record(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, 4, 4), diffuse = specular,
                 ldr = image_record(VK_FORMAT_R8G8B8A8_SRGB, kinds::colour, 4, 4), buffer;
  specular.resource = "lighting.specular";
  diffuse.resource = "lighting.diffuse";
  ldr.resource = "final.ldr";
  buffer.resource = "exposure.histogram";
  EXPECT_EQ(t.match("lighting.deferred", specular), &t.rules[0]);
  EXPECT_EQ(t.match("lighting.deferred", diffuse), &t.rules[1]);
  EXPECT_EQ(t.match("tonemap", ldr), &t.rules[2]);
  EXPECT_EQ(t.match("exposure", buffer), nullptr) << "'abs' cannot measure a buffer: its contract holds it";
  EXPECT_EQ(t.rules[1].description(), "rel <= 0.01, 0.1% of texels allowed over, 1 rectangle ignored");
  EXPECT_EQ(t.rules[1].source, file.string() + " rule 2");
  EXPECT_EQ(t.rules[0].description(), "exact");
  fs::remove(file);
}

TEST(Thresholds, MalformedFilesNameTheFileAndTheProblem) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{", "not JSON"},
      {R"({"rules": []})", "expected {\"thresholds\": [rules]}"},
      {R"({"thresholds": [{"match": "*", "metric": "abs", "limit": 1, "tolerance": 2}]})", "unknown key 'tolerance'"},
      {R"({"thresholds": [{"match": "*", "metric": "psnr", "limit": 1}]})", "'metric' must be one of"},
      {R"({"thresholds": [{"match": "*", "metric": "abs", "limit": -1}]})", "'limit' must be a finite number"},
      {R"({"thresholds": [{"match": "*", "metric": "abs"}]})", "'limit' must be a finite number"},
      {R"({"thresholds": [{"match": "*", "metric": "exact", "limit": 1}]})", "'exact' takes no limit"},
      {R"({"thresholds": [{"match": "*", "metric": "abs", "limit": 1, "allowed": 1.5}]})", "'allowed' must be"},
      {R"({"thresholds": [{"match": "", "metric": "abs", "limit": 1}]})", "'match' must be a glob"},
      {R"({"thresholds": [{"match": "*", "metric": "abs", "limit": 1, "ignore": [{"x": 0, "y": 0, "width": 0,
          "height": 4}]}]})",
       "an ignored rectangle is empty"},
      {R"({"thresholds": [{"match": "*", "metric": "abs", "limit": 1, "ignore": [{"x": -1, "y": 0, "width": 2,
          "height": 4}]}]})",
       "a rectangle is"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = write_file("bad" + std::to_string(i) + ".json", cases[i].first);
    try {
      read_thresholds(file.string());
      ADD_FAILURE() << "accepted " << cases[i].first;
    } catch (const ThresholdError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(cases[i].second), std::string::npos) << message;
    }
    fs::remove(file);
  }
  EXPECT_THROW(read_thresholds("/nonexistent/thresholds.json"), ThresholdError);
}

TEST(Thresholds, ConstantOffset) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 8, 4);
  const auto a = floats(std::vector<float>(32, 2.0f)), b = floats(std::vector<float>(32, 2.02f));
  const ThresholdCheck loose = check_threshold(rule(TexelMetric::abs, 0.03), frame(8, 4), r, a, b);
  EXPECT_TRUE(loose.holds);
  EXPECT_EQ(loose.counted, 32u);
  EXPECT_EQ(loose.over, 0u);
  EXPECT_NEAR(loose.worst, 0.02, 1e-6);
  const ThresholdCheck tight = check_threshold(rule(TexelMetric::abs, 0.01), frame(8, 4), r, a, b);
  EXPECT_FALSE(tight.holds);
  EXPECT_EQ(tight.over, 32u);
  // Relative: 0.02 / 2 = 1%.
  EXPECT_NEAR(check_threshold(rule(TexelMetric::rel, 1), frame(8, 4), r, a, b).worst, 0.01, 1e-6);
  EXPECT_TRUE(check_threshold(rule(TexelMetric::rel, 0.0101), frame(8, 4), r, a, b).holds);
}

TEST(Thresholds, SingleFireflyAllowedShareAndIgnoredRectangle) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 8, 4);
  std::vector<float> values(32, 1.0f);
  const auto a = floats(values);
  values[2 * 8 + 5] = 100.0f;  // texel (5, 2)
  const auto b = floats(values);
  const ThresholdCheck strict = check_threshold(rule(TexelMetric::abs, 0.1), frame(8, 4), r, a, b);
  EXPECT_FALSE(strict.holds);
  EXPECT_EQ(strict.over, 1u);
  EXPECT_EQ(strict.worst, 99.0);
  EXPECT_TRUE(check_threshold(rule(TexelMetric::abs, 0.1, 1.0 / 32), frame(8, 4), r, a, b).holds);
  EXPECT_FALSE(check_threshold(rule(TexelMetric::abs, 0.1, 0.99 / 32), frame(8, 4), r, a, b).holds);
  // The output is twice the image's size: texel (5, 2) is under output pixels (10..11, 4..5).
  const ThresholdCheck ignored =
      check_threshold(rule(TexelMetric::abs, 0.1, 0.0, {{10, 4, 2, 2}}), frame(16, 8), r, a, b);
  EXPECT_TRUE(ignored.holds);
  EXPECT_EQ(ignored.counted, 31u);
  EXPECT_FALSE(check_threshold(rule(TexelMetric::abs, 0.1, 0.0, {{12, 4, 2, 2}}), frame(16, 8), r, a, b).holds);
}

TEST(Thresholds, OnePixelShiftOfAnEdge) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 8, 4);
  std::vector<float> edge(32), shifted(32);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 8; ++x) {
      edge[y * 8 + x] = x >= 4 ? 1.0f : 0.0f;
      shifted[y * 8 + x] = x >= 5 ? 1.0f : 0.0f;
    }
  const ThresholdCheck check =
      check_threshold(rule(TexelMetric::abs, 0.5), frame(8, 4), r, floats(edge), floats(shifted));
  EXPECT_EQ(check.over, 4u) << "one column";
  EXPECT_EQ(check.worst, 1.0);
}

TEST(Thresholds, NanOnOneSideIsInfiniteAndOnBothIsAgreement) {
  const ResourceRecord r = image_record(VK_FORMAT_R32_SFLOAT, kinds::hdr_colour, 2, 1);
  const ThresholdCheck one =
      check_threshold(rule(TexelMetric::abs, 1e30), frame(2, 1), r, floats({1.0f, 1.0f}), floats({NAN, 1.0f}));
  EXPECT_EQ(one.over, 1u);
  EXPECT_TRUE(std::isinf(one.worst));
  const ThresholdCheck both =
      check_threshold(rule(TexelMetric::abs, 0), frame(2, 1), r, floats({NAN, 1.0f}), floats({NAN, 1.0f}));
  EXPECT_TRUE(both.holds);
  EXPECT_EQ(both.worst, 0.0);
}

TEST(Thresholds, AngleDepthCodesAndExactByKind) {
  // Normals 0.5n + 0.5 in RGBA16F: +X against +Y is 90 degrees.
  const ResourceRecord normals = image_record(VK_FORMAT_R32G32B32A32_SFLOAT, kinds::normal, 1, 1);
  const ThresholdCheck angle = check_threshold(rule(TexelMetric::angle, 89), frame(1, 1), normals,
                                               floats({1.0f, 0.5f, 0.5f, 0}), floats({0.5f, 1.0f, 0.5f, 0}));
  EXPECT_NEAR(angle.worst, 90.0, 1e-9);
  EXPECT_FALSE(angle.holds);
  // Reversed-Z device depth 0.1 against 0.11: distances znear/0.1 and znear/0.11 differ by 1/11.
  const ResourceRecord depth = image_record(VK_FORMAT_R32_SFLOAT, kinds::linear_depth, 1, 1);
  EXPECT_NEAR(check_threshold(rule(TexelMetric::depth, 1), frame(1, 1), depth, floats({0.1f}), floats({0.11f})).worst,
              1.0 / 11.0, 1e-6);
  // UNORM8: one code.
  const ResourceRecord ldr = image_record(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, 1, 1);
  const std::vector<uint8_t> a = {10, 20, 30, 255}, b = {10, 21, 30, 255};
  EXPECT_EQ(check_threshold(rule(TexelMetric::codes, 1), frame(1, 1), ldr, a, b).worst, 1.0);
  EXPECT_TRUE(check_threshold(rule(TexelMetric::codes, 1), frame(1, 1), ldr, a, b).holds);
  EXPECT_FALSE(check_threshold(rule(TexelMetric::exact, 0), frame(1, 1), ldr, a, b).holds);
  // A metric that does not fit the kind is a problem, not a pass.
  const ThresholdCheck unfit = check_threshold(rule(TexelMetric::angle, 1), frame(1, 1), ldr, a, a);
  EXPECT_FALSE(unfit.holds);
  EXPECT_NE(unfit.problem.find("'angle' measures normals"), std::string::npos) << unfit.problem;
  ResourceRecord buffer;
  buffer.is_buffer = true;
  EXPECT_FALSE(check_threshold(rule(TexelMetric::abs, 1), frame(1, 1), buffer, a, a).problem.empty());
  EXPECT_TRUE(check_threshold(rule(TexelMetric::exact, 0), frame(1, 1), buffer, a, a).holds);
  EXPECT_FALSE(check_threshold(rule(TexelMetric::exact, 0), frame(1, 1), buffer, a, b).holds);
}

TEST(Thresholds, FlipOfDisplayedColourPerPixel) {
  const ResourceRecord ldr = image_record(VK_FORMAT_R8G8B8A8_SRGB, kinds::colour, 16, 16);
  std::vector<uint8_t> a(16 * 16 * 4, 128), b;
  b = a;
  for (size_t i = 8 * 16 + 8, c = 0; c < 3; ++c) b[4 * i + c] = 255;  // one bright texel at (8, 8)
  const FlipResult flip = flip_displayed(ldr, a, b);
  const ThresholdCheck check = check_threshold(rule(TexelMetric::flip, 0.05), frame(16, 16), ldr, a, b);
  EXPECT_FLOAT_EQ(float(check.worst), float(flip.max));
  EXPECT_GT(flip.max, 0.05);
  EXPECT_EQ(check.over,
            uint64_t(std::count_if(flip.error.begin(), flip.error.end(), [](float e) { return e > 0.05f; })));
  EXPECT_EQ(check.counted, 256u);
  EXPECT_TRUE(check_threshold(rule(TexelMetric::flip, 0), frame(16, 16), ldr, a, a).holds);
  const ResourceRecord unorm = image_record(VK_FORMAT_R8G8B8A8_UNORM, kinds::material, 16, 16);
  EXPECT_NE(check_threshold(rule(TexelMetric::flip, 1), frame(16, 16), unorm, a, b).problem.find("'flip' measures"),
            std::string::npos);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
