// lighting.composite against a double-precision reference, every pixel:
// - lit: diffuse + specular + emissive + ambient·albedo·(1 − metallic), the ambient colour being
//   the `ambient` parameter × (0.8, 0.9, 1.2);
// - unlit (albedo alpha code 1, the G-buffer's unlit flag): albedo + emissive;
// - sky (device depth 0): the `sky` parameter × (0.5, 0.7, 1.6);
// - the ambient term × the material's occlusion (gbuffer.occlusion, random codes);
// - with ao.bent connected (an optional input), the ambient term × its alpha, the visibility;
// - without the sky's inputs, no image-based light (lighting_composite_ibl_test.cpp tests it);
// then limited to 65504, the largest finite half float (see below). Inputs are decoded from
// their formats as the GPU reads them (half floats, A2B10G10R10 and R8G8B8A8 UNORM codes,
// B10G11R11 floats, D32 depth) by decode_texel.
//
// Bound, with u = 2⁻²⁴ and A the ambient colour channel:
//   |GPU − reference| ≤ ½ half-float ULP of the reference + 12u·reference + 6u·A (9u·A with ao.bent).
// The half ULP is the R16G16B16A16_SFLOAT rounding (2⁻¹¹ relative at most; 2⁻²⁵ absolute among
// subnormals). The rest is the float arithmetic ahead of it: the ambient colour (parameter to
// float, × a float factor, product: 3u), UNORM decodes (2u each, allowing a multiply by a
// rounded 1/1023), two products and three sums of non-negative terms — 10u·reference — plus the
// error of 1 − metallic, absolute rather than relative (≤ 2u, times A·albedo ≤ A); 1u of margin
// for second-order terms, and 1u·reference + 1u·A for decode_texel's own float decode of the
// UNORM codes. The material's occlusion adds a product and a UNORM decode to the ambient term,
// 3u·A more, and a connected ao.bent as many again.
//
// The RGBA16F store: Vulkan leaves the rounding of a float to half open, and lavapipe truncates
// (Mesa's lp_build_float_to_half), so before the pass rounded to the nearest half itself it was
// up to a whole ULP low (2.0 half-ULPs measured here) and wrote 65504 for any larger sum, where
// a round-to-nearest store writes +Inf from 65520 on. The pass now writes the nearest half to
// min(sum, 65504), exact under either store; the test asserts no output is Inf or NaN.
#include <cmath>
#include <cstring>
#include <random>

#include "passes/core/format.h"
#include "passes/depth/kinds.h"
#include "passes/gbuffer/kinds.h"
#include "passes/lighting/stage.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr double U = 0x1p-24;
constexpr double HALF_MAX = 65504.0;

// One pixel's inputs as raw codes in the pass's input formats.
struct Pixel {
  uint16_t diffuse[3] = {}, specular[3] = {};
  uint32_t albedo = 0;       // A2B10G10R10: r | g << 10 | b << 20 | flags << 30
  uint8_t material[4] = {};  // metallic, roughness, translucency, emissive
  uint8_t occlusion = 255;   // the material's, R8_UNORM
  uint32_t emissive = 0;     // B10G11R11: r (11 bits) | g (11) << 11 | b (10) << 22
  float depth = 0.5f;
};

uint32_t albedo_word(uint32_t r, uint32_t g, uint32_t b, uint32_t flags) { return r | g << 10 | b << 20 | flags << 30; }

// B10G11R11 channels: 5-bit exponent over a 6-bit (R, G) or 5-bit (B) mantissa.
uint32_t emissive_word(uint32_t r, uint32_t g, uint32_t b) { return r | g << 11 | b << 22; }
constexpr uint32_t FLOAT11_MAX = 30u << 6 | 63u, FLOAT10_MAX = 30u << 5 | 31u;  // 65024

class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}
  uint32_t below(uint32_t n) { return engine_() % n; }
  // A finite non-negative float with `mantissa_bits` bits, uniform over exponents (subnormals
  // included); 0 one time in eight.
  uint32_t small_float(uint32_t mantissa_bits) {
    if (below(8) == 0) return 0;
    return below(31) << mantissa_bits | below(1u << mantissa_bits);
  }

 private:
  std::mt19937 engine_;
};

std::vector<Pixel> sweep(size_t count) {
  std::vector<Pixel> pixels;
  const uint16_t max = 0x7bff, h16 = 0x4c00, h8 = 0x4800;  // 65504, 16, 8
  // Near and above the half-float limit, and zeros.
  auto hdr = [&](uint16_t d, uint16_t s, uint32_t e, uint32_t albedo, uint8_t metallic) {
    Pixel p;
    std::fill(std::begin(p.diffuse), std::end(p.diffuse), d);
    std::fill(std::begin(p.specular), std::end(p.specular), s);
    p.emissive = emissive_word(e, e, e > FLOAT10_MAX ? FLOAT10_MAX : e);
    p.albedo = albedo;
    p.material[0] = metallic;
    pixels.push_back(p);
  };
  const uint32_t white = albedo_word(1023, 1023, 1023, 0), unlit_white = albedo_word(1023, 1023, 1023, 1);
  hdr(max, 0, 0, 0, 0);                    // 65504 exactly
  hdr(max, h8, 0, 0, 0);                   // 65512: rounds down to 65504
  hdr(max, h16, 0, 0, 0);                  // 65520: a tie, +Inf under a round-to-nearest store
  hdr(max, max, 0, 0, 0);                  // 131008
  hdr(max, max, FLOAT11_MAX, white, 0);    // every term large
  hdr(0, 0, FLOAT11_MAX, unlit_white, 0);  // unlit 1 + 65024
  hdr(0, 0, 0, 0, 0);                      // all zero
  hdr(0, 0, 0, white, 0);                  // ambient only
  hdr(0, 0, 0, white, 255);                // fully metallic: no ambient
  hdr(0, 0, 0, white, 254);                // 1 − metallic = 1/255
  Random rng(7);
  while (pixels.size() < count) {
    Pixel p;
    for (int c = 0; c < 3; ++c) {
      p.diffuse[c] = uint16_t(rng.small_float(10));
      p.specular[c] = uint16_t(rng.small_float(10));
    }
    const uint32_t kind = rng.below(16);  // 1 sky, 2 unlit, 13 lit
    p.albedo = albedo_word(rng.below(1024), rng.below(1024), rng.below(1024), kind >= 1 && kind <= 2);
    for (uint8_t& m : p.material) m = uint8_t(rng.below(256));
    p.occlusion = uint8_t(rng.below(256));
    p.emissive = emissive_word(rng.small_float(6), rng.small_float(6), rng.small_float(5));
    // Device depths of drawn surfaces are normal floats in (0, 1]; 0 is the sky.
    p.depth = kind == 0 ? 0.0f : std::ldexp(1.0f + float(rng.below(1u << 23)) * 0x1p-23f, -int(rng.below(30)) - 1);
    pixels.push_back(p);
  }
  return pixels;
}

double half_ulp(double x) { return x < 0x1p-14 ? 0x1p-25 : std::ldexp(1.0, std::ilogb(x) - 11); }

struct Params {
  double ambient, sky;
  int ao_code;  // ao.bent's alpha, the same at every texel; -1: no AO pass in the frame
};

class Composite : public GpuTest, public ::testing::WithParamInterface<Params> {};

TEST_P(Composite, IsTheNearestHalfOfTheDoubleReferenceUpToFloatError) {
  const auto [ambient, sky, ao_code] = GetParam();
  const uint32_t width = 256, height = 256;
  const size_t count = size_t(width) * height;
  const std::vector<Pixel> pixels = sweep(count);
  std::vector<uint8_t> occlusion(count);
  std::vector<uint8_t> diffuse(count * 8), specular(count * 8), albedo(count * 4), material(count * 4),
      emissive(count * 4), depth(count * 5, 0);
  for (size_t i = 0; i < count; ++i) {
    const Pixel& p = pixels[i];
    const uint16_t one = 0x3c00;
    const uint16_t d[4] = {p.diffuse[0], p.diffuse[1], p.diffuse[2], one};
    const uint16_t s[4] = {p.specular[0], p.specular[1], p.specular[2], one};
    std::memcpy(&diffuse[8 * i], d, 8);
    std::memcpy(&specular[8 * i], s, 8);
    std::memcpy(&albedo[4 * i], &p.albedo, 4);
    std::memcpy(&material[4 * i], p.material, 4);
    occlusion[i] = p.occlusion;
    std::memcpy(&emissive[4 * i], &p.emissive, 4);
    std::memcpy(&depth[4 * i], &p.depth, 4);  // the depth plane; the stencil plane follows
  }
  const auto hdr = [&](std::vector<uint8_t>& bytes) {
    return image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, width, height, bytes);
  };
  std::map<std::string, IsolatedInput> inputs{
      {"lighting.diffuse", hdr(diffuse)},
      {"lighting.specular", hdr(specular)},
      {"gbuffer.albedo", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::colour, width, height, albedo)},
      // Read by the image-based light alone, which needs the sky's inputs
      // (lighting_composite_ibl_test.cpp).
      {"gbuffer.occlusion", image(VK_FORMAT_R8_UNORM, kinds::occlusion, width, height, occlusion)},
      {"gbuffer.normal",
       image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal, width, height, std::vector<uint8_t>(count * 4, 0))},
      {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::material, width, height, material)},
      {"gbuffer.emissive", image(VK_FORMAT_B10G11R11_UFLOAT_PACK32, kinds::colour, width, height, emissive)},
      {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, width, height, depth)}};
  // AO at half size, as ao.gtao makes it; its bent normal varies, its visibility does not.
  std::vector<uint8_t> ao((width / 2) * (height / 2) * 4);
  for (size_t i = 0; i < ao.size(); ++i) ao[i] = i % 4 == 3 ? uint8_t(ao_code) : uint8_t(i * 37);
  if (ao_code >= 0)
    inputs.emplace("ao.bent", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, width / 2, height / 2, ao));
  const IsolatedRun result =
      run(lighting_composite_pass(), inputs, width, height, {{"ambient", ambient}, {"sky", sky}});
  // The input is left out of the pass where nothing produces it.
  bool reads_ao = false;
  for (const BoundUse& in : result.graph.passes.at(0).inputs) reads_ao |= in.resource == "ao.bent";
  EXPECT_EQ(reads_ao, ao_code >= 0);
  const std::vector<uint8_t>& out = *result.outputs.at("lighting.lit");
  ASSERT_EQ(out.size(), count * 8);

  const auto decode = [](VkFormat format, const std::vector<uint8_t>& bytes, size_t i, double* values) {
    float texel[4] = {};
    decode_texel(*format_info(format), 0, bytes, i, texel);
    for (int c = 0; c < 4; ++c) values[c] = texel[c];
  };
  const double visibility = ao_code >= 0 ? ao_code / 255.0 : 1.0;
  const double ambient_colour[3] = {ambient * 0.8 * visibility, ambient * 0.9 * visibility, ambient * 1.2 * visibility};
  const double sky_colour[3] = {sky * 0.5, sky * 0.7, sky * 1.6};
  double worst_half_ulps = 0;
  size_t limited = 0;
  for (size_t i = 0; i < count; ++i) {
    double d[4], s[4], a[4], m[4], e[4], z[4];
    decode(VK_FORMAT_R16G16B16A16_SFLOAT, diffuse, i, d);
    decode(VK_FORMAT_R16G16B16A16_SFLOAT, specular, i, s);
    decode(VK_FORMAT_A2B10G10R10_UNORM_PACK32, albedo, i, a);
    decode(VK_FORMAT_R8G8B8A8_UNORM, material, i, m);
    const double occluded = occlusion[i] / 255.0;
    decode(VK_FORMAT_B10G11R11_UFLOAT_PACK32, emissive, i, e);
    decode(VK_FORMAT_D32_SFLOAT_S8_UINT, depth, i, z);
    uint16_t lit[4];
    std::memcpy(lit, &out[8 * i], 8);
    for (int c = 0; c < 3; ++c) {
      const double sum = z[0] <= 0  ? sky_colour[c]
                         : a[3] > 0 ? a[c] + e[c]
                                    : d[c] + s[c] + e[c] + ambient_colour[c] * occluded * a[c] * (1.0 - m[0]);
      const double expected = std::min(sum, HALF_MAX);
      limited += sum > HALF_MAX;
      const double gpu = half_to_float(lit[c]);
      ASSERT_TRUE(std::isfinite(gpu)) << "pixel " << i << " channel " << c << ": expected " << expected;
      const double error = std::abs(gpu - expected);
      const double bound = half_ulp(expected) + 12 * U * sum + (ao_code >= 0 ? 9 : 6) * U * ambient_colour[c];
      worst_half_ulps = std::max(worst_half_ulps, error / half_ulp(expected));
      ASSERT_LE(error, bound) << "pixel " << i << " channel " << c << ": got " << gpu << ", expected " << expected;
    }
    ASSERT_EQ(lit[3], 0x3c00) << "alpha, pixel " << i;
  }
  std::printf(
      "lighting.composite ambient %g sky %g AO code %d: worst %.4f half-float half-ULPs; %zu channels limited to "
      "65504\n",
      ambient, sky, ao_code, worst_half_ulps, limited);
}

INSTANTIATE_TEST_SUITE_P(, Composite,
                         ::testing::Values(Params{0.02, 0.004, -1}, Params{0.0, 0.0, -1}, Params{1.0, 2.5, -1},
                                           Params{1e6, 1e6, -1}, Params{1.0, 2.5, 0}, Params{1.0, 2.5, 128},
                                           Params{1e6, 1e6, 255}));

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
