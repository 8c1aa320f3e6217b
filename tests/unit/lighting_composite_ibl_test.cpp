// lighting.composite's image-based light on a sphere in a uniform environment (sky.specular and
// sky.irradiance of radiance 1, no direct light, no ambient), against the split sum evaluated in
// double per pixel from the same DFG table (tests/unit/dfg_test.cpp holds the table to the
// BRDF) and the white furnace:
// - per pixel (n·v ≥ 0.3, away from the silhouette, where the depth's own normal is the
//   sphere's), random albedo, metalness and roughness: the double sum (1 − E)·albedo·(1 −
//   metallic) + E_ss + E_ms, E_ss = F0·A + B, E_ms Fdez-Agüera's (2019) compensation, within
//   2·10⁻³ relative (the half-float store, 10-bit normals, the GPU's bilinear weights);
// - the furnace: white dielectric and metal spheres over roughness 0…1 come out at 1 − what
//   single scattering loses, which is printed per roughness, and with the compensation at 1
//   within 2% (the metals the issue names; the dielectrics too);
// - the aerial perspective: surfaces from 5 m to 40 km through a volume of known content, against
//   the same blend in double (the test says how).
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <map>
#include <random>

#include "passes/ao/kinds.h"
#include "passes/core/format.h"
#include "passes/depth/kinds.h"
#include "passes/frame/gpu_types.h"
#include "passes/gbuffer/kinds.h"
#include "passes/lighting/dfg.h"
#include "passes/lighting/stage.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/atmosphere.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/kinds.h"
#include "tests/reference/ibl_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

constexpr uint32_t kSide = 96;
constexpr double kNear = 0.1;
const dvec3 kCentre(0.0, 0.0, -3.0);

struct Material {
  uint32_t albedo[3];  // 10-bit codes
  uint8_t metallic, roughness;
};

class CompositeIbl : public GpuTest {
 protected:
  // Reversed-Z, infinite far plane, Y flipped, 60° across: clip z = near, w = −z.
  static glm::dmat4 projection() {
    const double f = 1.0 / std::tan(glm::radians(30.0));
    glm::dmat4 p(0.0);
    p[0][0] = f;
    p[1][1] = -f;
    p[2][3] = -1.0;
    p[3][2] = kNear;
    return p;
  }
  // The sphere's point seen through pixel (x, y), if any.
  static std::optional<dvec3> sphere_point(uint32_t x, uint32_t y) {
    const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / double(kSide) * 2.0 - 1.0;
    const glm::dvec4 near_point = glm::inverse(projection()) * glm::dvec4(ndc, 1.0, 1.0);
    const dvec3 d = glm::normalize(dvec3(near_point) / near_point.w);
    const double b = glm::dot(d, kCentre), c = glm::dot(kCentre, kCentre) - 1.0, disc = b * b - c;
    if (disc < 0) return std::nullopt;
    return d * (b - std::sqrt(disc));
  }

  struct Frame {
    std::vector<uint8_t> depth, normal, albedo, material;
  };
  static Frame frame(const std::function<Material(uint32_t)>& material_of) {
    const size_t count = size_t(kSide) * kSide;
    Frame f{std::vector<uint8_t>(count * 5, 0), std::vector<uint8_t>(count * 4, 0), std::vector<uint8_t>(count * 4, 0),
            std::vector<uint8_t>(count * 4, 0)};
    for (uint32_t y = 0; y < kSide; ++y)
      for (uint32_t x = 0; x < kSide; ++x) {
        const size_t i = size_t(y) * kSide + x;
        const std::optional<dvec3> p = sphere_point(x, y);
        if (!p) continue;
        const float depth = float(kNear / -p->z);
        std::memcpy(&f.depth[4 * i], &depth, 4);
        const dvec3 n = *p - kCentre;
        uint32_t codes[3];
        for (int c = 0; c < 3; ++c) codes[c] = uint32_t(std::lround((n[c] * 0.5 + 0.5) * 1023.0));
        const uint32_t normal_word = codes[0] | codes[1] << 10 | codes[2] << 20;
        std::memcpy(&f.normal[4 * i], &normal_word, 4);
        const Material m = material_of(uint32_t(i));
        const uint32_t albedo_word = m.albedo[0] | m.albedo[1] << 10 | m.albedo[2] << 20;
        std::memcpy(&f.albedo[4 * i], &albedo_word, 4);
        f.material[4 * i] = m.metallic;
        f.material[4 * i + 1] = m.roughness;
      }
    return f;
  }

  static const std::vector<uint8_t>& dfg_table() {
    static const std::vector<uint8_t> table = *run(lighting_dfg_pass(), {}, 1, 1).outputs.at("lighting.dfg");
    return table;
  }

  static IsolatedRun composite(const Frame& f, bool multiple_scattering,
                               std::map<std::string, IsolatedInput> more_inputs = {}) {
    const size_t count = size_t(kSide) * kSide;
    GpuView camera{};
    camera.inverse_view_projection = glm::mat4(glm::inverse(projection()));
    camera.viewport = glm::vec4(kSide, kSide, 1.0f / kSide, 1.0f / kSide);
    GpuFrameConstants constants{};
    constants.camera_world = glm::vec4(0.0f, 1.7f, 0.0f, 1.0f);
    constants.sun_direction = glm::vec4(0.0f, -1.0f, 0.0f, 1.0f);
    GpuSkyIrradiance irradiance{};
    irradiance.coefficients[0] = glm::vec4(float(2.0 * std::sqrt(M_PI)));  // 1 / Y00: radiance 1 everywhere
    const ImageExtent specular_extent{64, 64, 1, kSkySpecularMips, 6};
    const uint64_t specular_texels = raw_image_bytes(*format_info(VK_FORMAT_R16G16B16A16_SFLOAT), specular_extent) / 8;
    std::vector<uint8_t> specular(specular_texels * 8);
    for (uint64_t t = 0; t < specular_texels * 4; ++t) {
      const uint16_t one = 0x3c00;
      std::memcpy(&specular[t * 2], &one, 2);
    }
    IsolatedInput specular_input = image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::sky_cube, 64, 64, specular);
    specular_input.desc.extent = specular_extent;
    specular_input.desc.cube = true;
    IsolatedInput dfg = image(VK_FORMAT_R16G16_SFLOAT, kinds::lookup_table, 32, 32, dfg_table());
    const std::vector<uint8_t> zeros(count * 8, 0);
    const auto hdr = [&](const std::vector<uint8_t>& bytes) {
      return image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, kSide, kSide, bytes);
    };
    std::map<std::string, IsolatedInput> inputs{
        {"lighting.diffuse", hdr(zeros)},
        {"lighting.specular", hdr(zeros)},
        {"gbuffer.albedo", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::colour, kSide, kSide, f.albedo)},
        {"gbuffer.normal", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal, kSide, kSide, f.normal)},
        {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::material, kSide, kSide, f.material)},
        {"gbuffer.occlusion",
         image(VK_FORMAT_R8_UNORM, kinds::occlusion, kSide, kSide, std::vector<uint8_t>(count, 255))},
        {"gbuffer.emissive",
         image(VK_FORMAT_B10G11R11_UFLOAT_PACK32, kinds::colour, kSide, kSide, std::vector<uint8_t>(count * 4, 0))},
        {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, kSide, kSide, f.depth)},
        {"frame.constants", record_input(constants)},
        {"frame.views", record_input(camera)},
        {"sky.atmosphere", record_input(earth_atmosphere({}))},
        {"sky.view",
         image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::sky_lut, 192, 108, std::vector<uint8_t>(192 * 108 * 8, 0))},
        {"sky.irradiance", record_input(irradiance)},
        {"sky.specular", specular_input},
        {"lighting.dfg", dfg}};
    inputs.merge(more_inputs);
    return run(lighting_composite_pass(), inputs, kSide, kSide,
               {{"ambient", 0.0}, {"multiple_scattering", multiple_scattering ? 1.0 : 0.0}});
  }

  // What the split sum gives at pixel i under radiance 1, in double from the decoded inputs: its
  // diffuse and specular parts, and the specular lobe's dominant direction and roughness.
  struct Parts {
    dvec3 diffuse, specular, r;
    double roughness;
  };
  static Parts expected_parts(const Frame& f, uint32_t x, uint32_t y, bool multiple_scattering,
                              double* n_v_out = nullptr) {
    const size_t i = size_t(y) * kSide + x;
    float a[4], n[4], m[4], depth;
    decode_texel(*format_info(VK_FORMAT_A2B10G10R10_UNORM_PACK32), 0, f.albedo, i, a);
    decode_texel(*format_info(VK_FORMAT_A2B10G10R10_UNORM_PACK32), 0, f.normal, i, n);
    decode_texel(*format_info(VK_FORMAT_R8G8B8A8_UNORM), 0, f.material, i, m);
    std::memcpy(&depth, &f.depth[4 * i], 4);
    const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / double(kSide) * 2.0 - 1.0;
    const glm::dvec4 p = glm::inverse(projection()) * glm::dvec4(ndc, depth, 1.0);
    const dvec3 v = glm::normalize(-dvec3(p) / p.w);
    const dvec3 normal = glm::normalize(dvec3(n[0], n[1], n[2]) * 2.0 - 1.0);
    const double n_v = std::clamp(glm::dot(normal, v), 1e-4, 1.0);
    if (n_v_out) *n_v_out = n_v;
    const glm::dvec2 dfg = reference::dfg_lookup(dfg_table(), 32, n_v, m[1]);
    const dvec3 albedo(a[0], a[1], a[2]);
    const dvec3 f0 = glm::mix(dvec3(0.04), albedo, double(m[0]));
    const dvec3 single = f0 * dfg.x + dfg.y;
    const double single_albedo = dfg.x + dfg.y;
    const dvec3 average = f0 + (1.0 - f0) / 21.0;
    const dvec3 multiple = multiple_scattering
                               ? single * average * (1.0 - single_albedo) / (1.0 - (1.0 - single_albedo) * average)
                               : dvec3(0.0);
    // Lagarde and de Rousiers' dominant direction (environment_light.glsl).
    const double alpha = double(m[1]) * m[1], smoothness = 1.0 - alpha;
    const dvec3 r =
        glm::normalize(glm::mix(normal, glm::reflect(-v, normal), smoothness * (std::sqrt(smoothness) + alpha)));
    return {albedo * (1.0 - double(m[0])) * (1.0 - single - multiple), single + multiple, r, double(m[1])};
  }
  // check(x, y, parts) at every pixel of the sphere seen at n·v ≥ 0.3 (the split sum's domain,
  // accuracy.md); how many there were.
  template <class Check>
  static int for_each_pixel_seen(const Frame& f, bool multiple_scattering, Check&& check) {
    int checked = 0;
    for (uint32_t y = 0; y < kSide; ++y)
      for (uint32_t x = 0; x < kSide; ++x) {
        double n_v;
        if (!inside(x, y)) continue;
        const Parts p = expected_parts(f, x, y, multiple_scattering, &n_v);
        if (n_v < 0.3) continue;
        check(x, y, p);
        ++checked;
        if (HasFatalFailure()) return checked;  // an ASSERT in `check` stops the loop, as in the test's own
      }
    return checked;
  }
  // Pixels of the sphere whose 8 neighbours are on it too (the depth's normal is the sphere's).
  static bool inside(uint32_t x, uint32_t y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (!sphere_point(uint32_t(int(x) + dx), uint32_t(int(y) + dy))) return false;
    return x > 0 && y > 0 && x + 1 < kSide && y + 1 < kSide;
  }
  static dvec3 lit_at(const IsolatedRun& run, uint32_t x, uint32_t y) {
    float t[4];
    decode_texel(*format_info(VK_FORMAT_R16G16B16A16_SFLOAT), 0, *run.outputs.at("lighting.lit"), size_t(y) * kSide + x,
                 t);
    return dvec3(t[0], t[1], t[2]);
  }
};

TEST_F(CompositeIbl, IsTheSplitSumInDoublePerPixel) {
  std::mt19937 rng(11);
  const Frame f = frame([&](uint32_t) {
    const uint32_t kind = rng() % 3;
    return Material{{uint32_t(rng() % 1024), uint32_t(rng() % 1024), uint32_t(rng() % 1024)},
                    uint8_t(kind == 0   ? 0
                            : kind == 1 ? 255
                                        : rng() % 256),
                    uint8_t(rng() % 256)};
  });
  for (const bool multiple : {true, false}) {
    const IsolatedRun result = composite(f, multiple);
    double worst = 0;
    const int checked = for_each_pixel_seen(f, multiple, [&](uint32_t x, uint32_t y, const Parts& p) {
      const dvec3 want = p.diffuse + p.specular, got = lit_at(result, x, y);
      for (int c = 0; c < 3; ++c) {
        const double relative = std::abs(got[c] - want[c]) / std::max(want[c], 1e-3);
        worst = std::max(worst, relative);
        ASSERT_LE(relative, 2e-3) << "pixel " << x << "," << y << " channel " << c << ": got " << got[c]
                                  << ", expected " << want[c];
      }
    });
    std::printf("composite image-based light (multiple scattering %s): %d pixels, largest relative error %.3g\n",
                multiple ? "on" : "off", checked, worst);
    EXPECT_GT(checked, 2000);
  }
}

TEST_F(CompositeIbl, WhiteFurnace) {
  for (const bool metal : {false, true})
    for (int step = 0; step <= 5; ++step) {
      const uint8_t roughness = uint8_t(std::lround(step / 5.0 * 255.0));
      const Frame f = frame([&](uint32_t) {
        return Material{{1023, 1023, 1023}, uint8_t(metal ? 255 : 0), roughness};
      });
      double with = 0, without = 0, predicted = 0;
      const IsolatedRun compensated = composite(f, true), single = composite(f, false);
      const int count = for_each_pixel_seen(f, false, [&](uint32_t x, uint32_t y, const Parts& p) {
        with += lit_at(compensated, x, y).x;
        without += lit_at(single, x, y).x;
        predicted += p.diffuse.x + p.specular.x;
      });
      with /= count;
      without /= count;
      predicted /= count;
      std::printf("white furnace, %s, roughness %.1f: single scattering %.4f (loses %.2f%%), compensated %.4f\n",
                  metal ? "metal" : "dielectric", step / 5.0, without, 100.0 * (1.0 - without), with);
      EXPECT_NEAR(without, predicted, 2e-3 * predicted) << "the split sum's single scattering";
      EXPECT_NEAR(with, 1.0, 0.02) << (metal ? "metal" : "dielectric") << " roughness " << step / 5.0;
    }
}

// The share of the specular lobe's cone (about r, half-angle `lobe`) inside the visibility cone
// (about `bent`, half-angle `visible`), integrated numerically over the lobe's cap: on each ring
// at angle t from r the visible arc is closed form, 2·acos((cos a − cos t cos d)/(sin t sin d)).
double cone_inside(dvec3 r, double lobe, dvec3 bent, double visible) {
  const double d = std::acos(std::clamp(glm::dot(r, bent), -1.0, 1.0)), lowest = std::cos(lobe);
  const int rings = 4000;
  double inside = 0;
  for (int i = 0; i < rings; ++i) {
    const double cos_t = lowest + (1.0 - lowest) * (i + 0.5) / rings, sin_t = std::sqrt(1.0 - cos_t * cos_t);
    const double denominator = sin_t * std::sin(d);
    const double x = denominator > 1e-12 ? (std::cos(visible) - cos_t * std::cos(d)) / denominator
                                         : (cos_t * std::cos(d) >= std::cos(visible) ? -1.0 : 1.0);
    inside += std::acos(std::clamp(x, -1.0, 1.0)) / M_PI;
  }
  return inside / rings;
}

// With ao.bent connected (one bent normal and visibility V everywhere): the diffuse part × V, and
// the specular × the share of its lobe's cone inside the visibility cone (half-angle asin √V).
// The lobe's cone (specular_occlusion.glsl) has its edge where GGX falls to half its peak,
// doubled to reflected directions: cos²θh = (1 − √2α²)/(1 − α²), min(2θh, π/2). Roughness from
// 0.2 (a narrower lobe makes the share a step of the float angle between the axes).
// Bound: 2·10⁻³ of the sum, as above, plus 10⁻² of the specular part: the share changes by up to
// 1/θ per radian of the angle between the axes, which the float view vector and acos move
// (0.0065 measured).
TEST_F(CompositeIbl, TheAoConeOccludesTheSpecularItDoesNotContain) {
  std::mt19937 rng(5);
  const Frame f = frame([&](uint32_t) {
    return Material{{uint32_t(rng() % 1024), uint32_t(rng() % 1024), uint32_t(rng() % 1024)},
                    uint8_t(rng() % 256),
                    uint8_t(51 + rng() % 205)};
  });
  const dvec3 bent = glm::normalize(dvec3(0.3, 0.8, 0.5));
  const uint8_t visibility_code = 153;
  std::vector<uint8_t> ao;
  uint8_t bent_codes[3];
  for (int c = 0; c < 3; ++c) bent_codes[c] = uint8_t(std::lround((bent[c] * 0.5 + 0.5) * 255));
  for (uint32_t i = 0; i < (kSide / 2) * (kSide / 2); ++i)
    ao.insert(ao.end(), {bent_codes[0], bent_codes[1], bent_codes[2], visibility_code});
  const dvec3 stored_bent = glm::normalize(dvec3(bent_codes[0], bent_codes[1], bent_codes[2]) / 255.0 * 2.0 - 1.0);
  const double visibility = visibility_code / 255.0, visible = std::asin(std::sqrt(visibility));
  const IsolatedRun result =
      composite(f, true, {{"ao.bent", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour, kSide / 2, kSide / 2, ao)}});
  double worst = 0, least_share = 1, most_share = 0, worst_share = 0;
  const int checked = for_each_pixel_seen(f, true, [&](uint32_t x, uint32_t y, const Parts& p) {
    const double alpha2 = std::pow(p.roughness, 4.0);
    const double cos2 = (1.0 - std::sqrt(2.0) * alpha2) / (1.0 - alpha2);
    const double lobe = cos2 <= 0 ? M_PI / 2 : std::min(2.0 * std::acos(std::sqrt(cos2)), M_PI / 2);
    const double share = cone_inside(p.r, lobe, stored_bent, visible);
    least_share = std::min(least_share, share);
    most_share = std::max(most_share, share);
    const dvec3 want = p.diffuse * visibility + p.specular * share;
    const dvec3 got = lit_at(result, x, y);
    for (int c = 0; c < 3; ++c) {
      const double error = std::abs(got[c] - want[c]);
      worst = std::max(worst, error / std::max(want[c], 1e-3));
      if (p.specular[c] > 0.01)
        worst_share = std::max(worst_share, std::max(0.0, error - 2e-3 * want[c]) / p.specular[c]);
      ASSERT_LE(error, 2e-3 * want[c] + 0.01 * p.specular[c])
          << "pixel " << x << "," << y << " channel " << c << ": got " << got[c] << ", expected " << want[c]
          << " (specular share " << share << ")";
    }
  });
  std::printf("AO cone: %d pixels, specular shares %.3f…%.3f, largest relative error %.3g, of the share %.4f\n",
              checked, least_share, most_share, worst, worst_share);
  EXPECT_GT(checked, 2000);
  EXPECT_LT(least_share, 0.05);  // lobes outside the cone, inside it and across its edge
  EXPECT_GT(most_share, 0.95);
}

// The aerial perspective over unlit surfaces (whose lit value is their albedo) at distances d from
// 5 m to 40 km (beyond the volume's 32 km): each comes out as albedo · exp(−k·d) + L·d, with L and
// k the in-scattering and optical depth per km the volume holds at the pixel's slice coordinate
// (composite.frag's through_air), in double. The volume (20×12×24, not square, to tell its axes
// apart) holds values linear in each texel coordinate and exact in half floats, so the sampler's
// trilinear read is the linear function itself.
TEST_F(CompositeIbl, SurfacesAreSeenThroughTheAerialPerspective) {
  constexpr uint32_t kW = 20, kH = 12, kSlices = 24;
  const auto in_scattered = [](double x, double y, double z) {
    return dvec3((x + 1) / 1024, (y + 1) / 512, (z + 1) / 256);
  };
  const auto optical_depth = [](double z) { return (z + 1) / 1024; };
  std::vector<uint8_t> volume(size_t(kW) * kH * kSlices * 8);
  for (uint32_t z = 0; z < kSlices; ++z)
    for (uint32_t y = 0; y < kH; ++y)
      for (uint32_t x = 0; x < kW; ++x) {
        const dvec3 l = in_scattered(x, y, z);
        const uint16_t texel[4] = {float_to_half(float(l.x)), float_to_half(float(l.y)), float_to_half(float(l.z)),
                                   float_to_half(float(optical_depth(z)))};
        std::memcpy(&volume[((size_t(z) * kH + y) * kW + x) * 8], texel, 8);
      }
  IsolatedInput air = image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::aerial_perspective, kW, kH, volume);
  air.desc.extent.depth = kSlices;

  // Unlit pixels at view depths spread logarithmically from 5 m to 40 km, grey albedo.
  const size_t count = size_t(kSide) * kSide;
  Frame f{std::vector<uint8_t>(count * 5, 0), std::vector<uint8_t>(count * 4, 0), std::vector<uint8_t>(count * 4, 0),
          std::vector<uint8_t>(count * 4, 0)};
  std::vector<double> view_depth(count);
  for (size_t i = 0; i < count; ++i) {
    view_depth[i] = 5.0 * std::pow(8000.0, double((i * 7919) % count) / double(count - 1));
    const float depth = float(kNear / view_depth[i]);
    std::memcpy(&f.depth[4 * i], &depth, 4);
    const uint32_t albedo_word = 512u | 512u << 10 | 512u << 20 | 3u << 30;  // alpha > 0: unlit
    std::memcpy(&f.albedo[4 * i], &albedo_word, 4);
  }
  const IsolatedRun result = composite(f, true, {{"sky.aerial_perspective", air}});
  const double albedo = 512.0 / 1023.0;
  double worst = 0;
  for (uint32_t y = 0; y < kSide; ++y)
    for (uint32_t x = 0; x < kSide; ++x) {
      const size_t i = size_t(y) * kSide + x;
      const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / double(kSide) * 2.0 - 1.0;
      const glm::dvec4 p = glm::inverse(projection()) * glm::dvec4(ndc, kNear / view_depth[i], 1.0);
      const double distance_km = glm::length(dvec3(p) / p.w) * 1e-3;
      const double slice = kSlices * std::sqrt(distance_km / kSkyAerialDistanceKm) - 1.0;
      const glm::dvec2 uv = (glm::dvec2(x, y) + 0.5) / double(kSide);
      const double tx = std::clamp(uv.x * kW - 0.5, 0.0, kW - 1.0), ty = std::clamp(uv.y * kH - 0.5, 0.0, kH - 1.0);
      const double tz = std::clamp(slice, 0.0, kSlices - 1.0);
      const dvec3 want = albedo * std::exp(-optical_depth(tz) * distance_km) + in_scattered(tx, ty, tz) * distance_km;
      const dvec3 got = lit_at(result, x, y);
      for (int c = 0; c < 3; ++c) {
        const double relative = std::abs(got[c] - want[c]) / want[c];
        worst = std::max(worst, relative);
        ASSERT_LE(relative, 2e-3) << "pixel " << x << "," << y << " at " << distance_km << " km, channel " << c
                                  << ": got " << got[c] << ", expected " << want[c];
      }
    }
  std::printf("composite aerial perspective: %zu pixels, largest relative error %.3g\n", count, worst);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
