// tonemap against a double-precision reference over every half-float input: colour × exposure
// (the manual one, times exposure.value.x when the exposure pass wrote one, i.e. it is > 0),
// Narkowicz's ACES fit clamped to [0, 1], then the exact sRGB OETF (12.92·x up to 0.0031308,
// 1.055·x^(1/2.4) − 0.055 above) and rounding to the nearest 8-bit code, which is what the
// R8G8B8A8_SRGB target stands for. Negative channels give 0; a pixel with a NaN channel (after
// the exposure, so 0 × Inf counts) is black; +Inf takes the curve's limit, 2.51/2.43, clamped
// to 1.
//
// Bound: |GPU code − 255·OETF(ACES(x))| ≤ 0.67, measured on the continuous value: a correctly
// rounded encoder would stay within 0.5 plus the float error of the curve (< 10⁻³ code), but
// lavapipe's is not correctly rounded. Mesa's lp_build_linear_to_srgb evaluates
// a·x^0.375 + b·x^0.5 + c with fast reciprocal square roots, an approximation its comment puts
// at ±0.17 codes before rounding to the nearest integer; 0.5 + 0.17 is the bound, so every code
// is within 1 of the correctly rounded one. The worst case measured here (printed) sits just
// above the OETF's linear segment, near code 10.6.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/core/format.h"
#include "passes/core/graph.h"
#include "passes/post/stage.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr double BOUND = 0.5 + 0.17;

double aces(double x) {
  if (std::isinf(x)) return 1.0;
  return std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

double srgb_oetf(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }

// Every half bit pattern in each channel: rows 0..255 carry pattern i in R, G and B alike;
// rows 256..511 rotate the patterns between channels, so a channel mix-up shows and a NaN in
// one channel must black out finite neighbours.
std::vector<uint16_t> every_half_pattern() {
  std::vector<uint16_t> texels;
  for (uint32_t layout = 0; layout < 2; ++layout)
    for (uint32_t i = 0; i < 65536; ++i) {
      const uint32_t step = layout ? 21845 : 0;
      texels.insert(texels.end(), {uint16_t(i), uint16_t(i + step), uint16_t(i + 2 * step), 0x3c00});
    }
  return texels;
}

// exposure.value as the exposure pass writes it: x is the automatic scale (0: none).
IsolatedInput exposure_value(float automatic) {
  const float texel[4] = {automatic, 0.0f, 0.0f, 0.0f};
  std::vector<uint8_t> bytes(sizeof texel);
  std::memcpy(bytes.data(), texel, sizeof texel);
  IsolatedInput input;
  input.desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  input.desc.kind = kinds::hdr_colour;
  input.bytes = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
  return input;
}

struct Exposures {
  double manual, automatic;
};

class Tonemap : public GpuTest, public ::testing::WithParamInterface<Exposures> {};
class TonemapBloom : public GpuTest {};

TEST_P(Tonemap, StaysWithinTheBoundOfTheExactAcesAndSrgbEncoding) {
  const auto [manual, automatic] = GetParam();
  const double exposure = manual * (automatic > 0 ? double(float(automatic)) : 1.0);
  const uint32_t width = 256, height = 512;
  const std::vector<uint16_t> texels = every_half_pattern();
  std::vector<uint8_t> bytes(texels.size() * 2);
  std::memcpy(bytes.data(), texels.data(), bytes.size());
  // No bloom here: a chain of zeros adds nothing (TonemapBloom covers it).
  IsolatedInput chain = image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width / 2, height / 2, {});
  chain.desc.extent.mips = kBloomLevels;
  chain.bytes = std::make_shared<const std::vector<uint8_t>>(chain.desc.raw_bytes(), 0);
  const IsolatedRun result =
      run(tonemap_pass("lighting.lit"),
          {{"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height, bytes)},
           {"exposure.value", exposure_value(float(automatic))},
           {"bloom.chain", chain}},
          width, height, {{"exposure", manual}});
  const std::vector<uint8_t>& out = *result.outputs.at("final.ldr");
  ASSERT_EQ(out.size(), size_t(width) * height * 4);

  double worst = 0;
  size_t off_by_one = 0;
  for (size_t p = 0; p < size_t(width) * height; ++p) {
    double x[3];
    bool any_nan = false;
    for (int c = 0; c < 3; ++c) {
      x[c] = double(half_to_float(texels[4 * p + c])) * exposure;
      any_nan |= std::isnan(x[c]);
    }
    ASSERT_EQ(out[4 * p + 3], 255) << "alpha, pixel " << p;
    for (int c = 0; c < 3; ++c) {
      const double exact = any_nan ? 0.0 : 255.0 * srgb_oetf(aces(std::max(x[c], 0.0)));
      const int code = out[4 * p + c];
      const double error = std::abs(code - exact);
      worst = std::max(worst, error);
      off_by_one += code != int(std::lround(exact));
      ASSERT_LE(error, BOUND) << "pixel " << p << " channel " << c << " input 0x" << std::hex << texels[4 * p + c]
                              << std::dec << " × " << exposure << ": code " << code << ", exact " << exact;
    }
  }
  std::printf(
      "tonemap exposure %g: worst %.4f codes from the exact encoding; %zu of %zu channels not the nearest code\n",
      exposure, worst, off_by_one, size_t(width) * height * 3);
}

// Manual alone (no automatic exposure, 0), automatic alone, and both; a negative automatic value
// (never written by the exposure pass) counts as none.
INSTANTIATE_TEST_SUITE_P(, Tonemap,
                         ::testing::Values(Exposures{1.0, 0.0}, Exposures{0.25, 0.0}, Exposures{3.7, 0.0},
                                           Exposures{1e-3, 0.0}, Exposures{1e6, 0.0}, Exposures{0.0, 0.0},
                                           Exposures{1.0, 0.37}, Exposures{2.0, 11.5}, Exposures{1.0, -1.0}));

// The bloom term: lit colour + weight × the mean over bloom.chain's levels of each level
// interpolated bilinearly at the pixel centre (uv = (x + ½)/width; texel t = uv·size − ½, the
// four nearest texels clamped into the level), through the same curve. The bound gains 0.01 of
// a code for the float arithmetic of the interpolation (relative 1e-6, times the curve's slope).
TEST_F(TonemapBloom, AddsTheMeanOfTheLevelsInterpolatedAtThePixelCentre) {
  const uint32_t width = 37, height = 23, chain_width = 19, chain_height = 12;
  const double weight = 0.5, lit = 0.1;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(0.0f, 4.0f);
  IsolatedInput chain = image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, chain_width, chain_height, {});
  chain.desc.extent.mips = full_mip_count(chain_width, chain_height);
  std::vector<uint16_t> codes(chain.desc.raw_bytes() / 2);
  for (uint16_t& c : codes) c = float_to_half(value(rng));
  std::vector<uint8_t> chain_bytes(codes.size() * 2);
  std::memcpy(chain_bytes.data(), codes.data(), chain_bytes.size());
  chain.bytes = std::make_shared<const std::vector<uint8_t>>(chain_bytes);
  std::vector<uint16_t> lit_codes(size_t(width) * height * 4, float_to_half(float(lit)));
  std::vector<uint8_t> lit_bytes(lit_codes.size() * 2);
  std::memcpy(lit_bytes.data(), lit_codes.data(), lit_bytes.size());
  const IsolatedRun result =
      run(tonemap_pass("lighting.lit"),
          {{"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height, lit_bytes)},
           {"exposure.value", exposure_value(0.0f)},
           {"bloom.chain", chain}},
          width, height, {{"bloom", weight}});
  const std::vector<uint8_t>& out = *result.outputs.at("final.ldr");
  const FormatInfo f = *format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  auto texel = [&](uint32_t level, int64_t x, int64_t y, int c) {
    const int64_t w = mip_size(chain_width, level), h = mip_size(chain_height, level);
    x = std::clamp<int64_t>(x, 0, w - 1);
    y = std::clamp<int64_t>(y, 0, h - 1);
    const size_t index = raw_subresource_offset(f, chain.desc.extent, 0, level, 0) / 2 + 4 * size_t(y * w + x) + c;
    return double(half_to_float(codes[index]));
  };
  double worst = 0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        double bloom = 0;
        for (uint32_t level = 0; level < chain.desc.extent.mips; ++level) {
          const double tx = (x + 0.5) / width * mip_size(chain_width, level) - 0.5;
          const double ty = (y + 0.5) / height * mip_size(chain_height, level) - 0.5;
          const double x0 = std::floor(tx), y0 = std::floor(ty), fx = tx - x0, fy = ty - y0;
          const auto at = [&](double dx, double dy) { return texel(level, int64_t(x0 + dx), int64_t(y0 + dy), c); };
          bloom += (1 - fy) * ((1 - fx) * at(0, 0) + fx * at(1, 0)) + fy * ((1 - fx) * at(0, 1) + fx * at(1, 1));
        }
        bloom /= chain.desc.extent.mips;
        const double exact = 255.0 * srgb_oetf(aces(double(half_to_float(float_to_half(float(lit)))) + weight * bloom));
        const double error = std::abs(out[4 * (size_t(y) * width + x) + c] - exact);
        worst = std::max(worst, error);
        ASSERT_LE(error, BOUND + 0.01) << "pixel " << x << "," << y << " channel " << c;
      }
  std::printf("tonemap with bloom: worst %.4f codes from the exact encoding\n", worst);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
