// exposure against a double-precision CPU reference: the 256-bin histogram of log2 luminance
// (Rec. 709 weights) over [log2_min, log2_max), its mean at the bin centres, and the exponential
// adaptation adapted = measured + (previous − measured)·exp(−Δt/τ) from the previous frame's
// value (none when that is 0), scale = key / 2^adapted, with a given key or Krawczyk et al.'s
// key(L) = 1.03 − 2 / (2 + log10(L + 1)) of the adapted mean L.
//
// Bounds. Histogram: the GPU's log2 may put a pixel whose exact bin position lies within 10⁻⁴
// of a bin edge into the neighbouring bin; every other pixel lands in the reference's bin, so
// the L1 distance between the histograms is at most twice the number of such pixels. Value:
// the mean is a float tree sum of 256 products (relative error < 2⁻²⁴·8 each way), the
// adaptation one float exp and mix: |adapted − reference| ≤ 10⁻⁵ + moved·bin_width/N log2 units,
// and the scale within the same relative bound times ln 2 (allowing for float exp2).
#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "passes/core/format.h"
#include "passes/frame/gpu_types.h"
#include "passes/post/stage.h"
#include "tests/reference/exposure_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr double kLog2Min = -12, kLog2Max = 12;

struct Rgb {
  float r, g, b;
};

using Reference = reference::ExposureHistogram;

// The reference over the half-float texels the pass reads.
Reference reference(const std::vector<Rgb>& pixels) {
  std::vector<std::array<double, 3>> rgb;
  for (const Rgb& p : pixels)
    rgb.push_back(
        {half_to_float(float_to_half(p.r)), half_to_float(float_to_half(p.g)), half_to_float(float_to_half(p.b))});
  return reference::exposure_histogram(rgb, kLog2Min, kLog2Max);
}

class Exposure : public GpuTest {
 protected:
  struct Result {
    std::vector<uint32_t> histogram;
    float value[4];
  };

  static IsolatedInput rgba32f_texel(const float (&texel)[4]) {
    std::vector<uint8_t> bytes(16);
    std::memcpy(bytes.data(), texel, 16);
    return image(VK_FORMAT_R32G32B32A32_SFLOAT, kinds::hdr_colour, 1, 1, std::move(bytes));
  }

  static Result expose(const std::vector<Rgb>& pixels, uint32_t width, uint32_t height, const float (&history)[4],
                       ParamValues params = {}) {
    std::vector<uint16_t> texels;
    for (const Rgb& p : pixels)
      texels.insert(texels.end(), {float_to_half(p.r), float_to_half(p.g), float_to_half(p.b), 0x3c00});
    std::vector<uint8_t> lit(texels.size() * 2);
    std::memcpy(lit.data(), texels.data(), lit.size());
    GpuFrameConstants frame{};
    frame.timing = {1.0f, float(kFrameSeconds), 0.0f, 0.0f};
    IsolatedInput constants;
    constants.desc.is_buffer = true;
    constants.desc.buffer_size = sizeof frame;
    auto frame_bytes = std::make_shared<std::vector<uint8_t>>(sizeof frame);
    std::memcpy(frame_bytes->data(), &frame, sizeof frame);
    constants.bytes = frame_bytes;
    const IsolatedRun run_result =
        run(exposure_pass("lighting.lit"),
            {{"frame.constants", constants},
             {"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height, lit)},
             {previous("exposure.value"), rgba32f_texel(history)}},
            width, height, params);
    Result r;
    const auto& histogram = *run_result.outputs.at("exposure.histogram");
    r.histogram.resize(histogram.size() / 4);
    std::memcpy(r.histogram.data(), histogram.data(), histogram.size());
    std::memcpy(r.value, run_result.outputs.at("exposure.value")->data(), 16);
    return r;
  }

  // `key` 0: the automatic key.
  static void expect_matches(const Result& got, const Reference& ref, size_t pixels, double previous_adapted,
                             bool has_history, double adapt_seconds = 1.0, double key = 0.0) {
    ASSERT_EQ(got.histogram.size(), kExposureBins);
    uint64_t l1 = 0;
    for (size_t i = 0; i < kExposureBins; ++i)
      l1 += uint64_t(std::llabs(int64_t(got.histogram[i]) - int64_t(ref.bins[i])));
    EXPECT_LE(l1, 2 * ref.near_edges) << "histogram differs beyond pixels on bin edges";
    const double width = (kLog2Max - kLog2Min) / kExposureBins;
    const double bound = 1e-5 + double(ref.near_edges) * width / double(std::max<size_t>(pixels, 1));
    const double adapted = has_history
                               ? reference::adapt_exposure(ref.measured, previous_adapted, kFrameSeconds, adapt_seconds)
                               : ref.measured;
    EXPECT_NEAR(got.value[2], ref.measured, bound) << "measured mean log2 luminance";
    EXPECT_NEAR(got.value[1], adapted, bound) << "adapted log2 luminance";
    const double mean = std::exp2(adapted);
    const double scale = (key > 0 ? key : reference::automatic_key(mean)) / mean;
    EXPECT_NEAR(got.value[0], scale, scale * (bound * std::log(2.0) + 1e-6)) << "exposure scale";
  }
};

std::vector<Rgb> random_image(size_t count, double log2_low, double log2_high, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(log2_low, log2_high), tint(0.2, 1.0);
  std::vector<Rgb> pixels(count);
  for (Rgb& p : pixels) {
    const double l = std::exp2(level(rng));
    p = {float(l * tint(rng)), float(l * tint(rng)), float(l * tint(rng))};
  }
  return pixels;
}

TEST_F(Exposure, FirstFrameExposesForTheHistogramMean) {
  const uint32_t width = 173, height = 61;  // not a multiple of the 16×16 workgroup
  const auto pixels = random_image(size_t(width) * height, -14, 14, 1);
  const float none[4] = {0, 0, 0, 0};
  expect_matches(expose(pixels, width, height, none), reference(pixels), pixels.size(), 0, false);
}

TEST_F(Exposure, AdaptsTowardTheMeasuredValueOverFrames) {
  // A dark shot, then a bright one: the adapted value follows the exponential, frame by frame.
  const uint32_t width = 64, height = 48;
  const auto dark = random_image(size_t(width) * height, -8, -4, 2);
  const auto bright = random_image(size_t(width) * height, 2, 6, 3);
  float previous[4] = {0, 0, 0, 0};
  double adapted = 0;
  for (int frame = 0; frame < 6; ++frame) {
    const auto& pixels = frame == 0 ? dark : bright;
    const Reference ref = reference(pixels);
    const Result got = expose(pixels, width, height, previous);
    expect_matches(got, ref, pixels.size(), adapted, frame > 0);
    adapted = got.value[1];
    std::memcpy(previous, got.value, sizeof previous);
  }
  // After five frames of a τ = 1 s adaptation the view is still far from the bright target.
  const double target = reference(bright).measured;
  std::printf("exposure: dark shot %.4f, bright target %.4f, adapted after 5 frames %.4f (log2 luminance)\n",
              reference(dark).measured, target, adapted);
  EXPECT_LT(adapted, target - 5.0);
}

TEST_F(Exposure, ZeroTimeConstantAdaptsInstantly) {
  const auto pixels = random_image(32 * 32, 0, 3, 4);
  const float previous[4] = {0.18f / float(std::exp2(-6.0)), -6.0f, -6.0f, 0.0f};
  expect_matches(expose(pixels, 32, 32, previous, {{"adapt_seconds", 0.0}, {"key", 0.18}}), reference(pixels),
                 pixels.size(), -6.0, true, 0.0, 0.18);
}

TEST_F(Exposure, TheAutomaticKeyKeepsADarkSceneDarkerThanABrightOne) {
  // Middle grey for everything would turn night into day: the automatic key exposes a scene
  // whose mean is 2^-6 to well below the 0.18 a fixed key would give it.
  const auto night = random_image(32 * 32, -7, -5, 6);
  const float none[4] = {0, 0, 0, 0};
  const Result got = expose(night, 32, 32, none);
  const double exposed_mean = got.value[0] * std::exp2(double(got.value[1]));
  std::printf("exposure: a scene of mean 2^%.2f is exposed to %.4f (automatic key)\n", got.value[1], exposed_mean);
  EXPECT_LT(exposed_mean, 0.05);
  expect_matches(got, reference(night), night.size(), 0, false);
}

TEST_F(Exposure, NaNsAreIgnoredInfinitiesAndDarknessClampToTheEndBins) {
  // Stress: NaN, ±Inf, zero, negative, denormal-small and half-max pixels among ordinary ones.
  auto pixels = random_image(40 * 30, -3, 3, 5);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const Rgb hostile[] = {{nan, 1, 1},  {inf, inf, inf}, {-inf, 0, 0},         {0, 0, 0},
                         {-5, -5, -5}, {1e-7f, 0, 0},   {65504, 65504, 65504}};
  for (size_t i = 0; i < pixels.size(); i += 7) pixels[i] = hostile[(i / 7) % std::size(hostile)];
  const float none[4] = {0, 0, 0, 0};
  const Result got = expose(pixels, 40, 30, none);
  const Reference ref = reference(pixels);
  expect_matches(got, ref, pixels.size(), 0, false);
  uint64_t counted = 0;
  for (uint32_t c : got.histogram) counted += c;
  EXPECT_LT(counted, pixels.size()) << "NaN pixels are not counted";
  for (float v : got.value) EXPECT_TRUE(std::isfinite(v));
}

TEST_F(Exposure, AnImageOfNaNsKeepsThePreviousValueOrLeavesExposureManual) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Rgb> pixels(16 * 16, Rgb{nan, nan, nan});
  const float previous[4] = {0.5f, 1.5f, 1.25f, 0.0f};
  const Result kept = expose(pixels, 16, 16, previous);
  for (uint32_t c : kept.histogram) EXPECT_EQ(c, 0u);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(kept.value[k], previous[k]);
  const float none[4] = {0, 0, 0, 0};
  const Result manual = expose(pixels, 16, 16, none);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(manual.value[k], 0.0f) << "0: tonemap uses its manual exposure alone";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
