// The reflection probes' array and the composite's lookup of it, against references in double
// (tests/reference/ibl_reference.h: cube faces by Vulkan's face selection, seamless bilinear
// lookups, GGX's prefilter from many samples of level 0):
// - the dual-paraboloid parameterisation (paraboloid.glsl.h): every texel centre of a 256²
//   hemisphere, to its direction and back, within ½ texel;
// - probes.convert on a synthetic capture (a street-like environment: a sky, a dark ground and
//   rows of bright windows, whose edges the prefilter must not alias), into slot 3 of the array:
//   level 0 the capture's cube read along each texel's direction within half-float rounding
//   (2⁻¹⁰ relative) of the bilinear reference; across the seam, the two hemispheres read at the
//   rim (the equator) within 2% of each other's radiance plus 1% of the environment's mean; each
//   prefiltered level against the double prefilter converged (32768 samples: 1024 were 0.9% to
//   6.6% from it here), RMSE relative to the reference's RMS: ≤ 1% at every mip with 255 samples
//   at mip 1 (4× more each mip down); at the default 64, ≤ 1% from mip 3 and ≤ 3% at mips 1 and
//   2 (measured 2.7% and 1.5%: the windows, 40 times the sky, are few samples' worth of a narrow
//   lobe); every other slot keeps what the array held; the same on the map's street probe's own
//   capture;
// - parallax_direction() and probe_texel() (reflection.glsl) on the GPU against a CPU ray–box
//   intersection in double: the corrected direction within 10⁻⁴ rad, the texel coordinates
//   within 10⁻⁵ of the double ones.
#include <glm/gtc/packing.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "passes/assembly/renderer.h"
#include "passes/core/shader.h"
#include "passes/frame/gpu_types.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/paraboloid.glsl.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "tests/reference/ibl_reference.h"
#include "tests/reference/probe_capture.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec2;
using glm::dvec3;
using reference::half4_at;
using reference::kHalf4;
using reference::put_half4;

constexpr uint32_t kFaceSide = 64, kArraySide = 256, kSlot = 3;
// The prefilter's reference: 1024 samples (accuracy.md's figure) were 1% to 4.6% (RMSE) from
// 32768 on this environment, whose windows are 40 times the sky's radiance.
constexpr uint32_t kReferenceSamples = 32768;

class ProbesArrayTest : public GpuTest {
 protected:
  static constexpr uint32_t kMips = kProbeArrayMips, kLayers = 2 * kProbeSlots;
  static inline const ImageExtent kArray{kArraySide, kArraySide, 1, kMips, kLayers};
  // What the array held before this frame's capture, everywhere.
  static inline const dvec3 kBefore{0.25, 0.5, 0.75};

  static IsolatedRun convert(const reference::ProbeCapture& capture, uint32_t samples = 64) {
    return run(probes_convert_pass(), reference::convert_inputs(capture, kSlot, kArraySide, kBefore), 1, 1,
               {{"samples", double(samples)}});
  }
  static dvec3 texel(const std::vector<uint8_t>& array, uint32_t mip, uint32_t layer, uint32_t x, uint32_t y) {
    const uint32_t side = mip_size(kArraySide, mip);
    return half4_at(array,
                    raw_subresource_offset(*format_info(kHalf4), kArray, 0, mip, layer) + (uint64_t(y) * side + x) * 8);
  }
  // Bilinear at (u, v) in [0, 1]² of one layer's level, clamped at its edges, as the composite's
  // sampler reads it.
  static dvec3 bilinear(const std::vector<uint8_t>& array, uint32_t mip, uint32_t layer, dvec2 uv) {
    const double side = mip_size(kArraySide, mip);
    const double x = uv.x * side - 0.5, y = uv.y * side - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
    auto at = [&](double xi, double yi) {
      return texel(array, mip, layer, uint32_t(std::clamp(xi, 0.0, side - 1)), uint32_t(std::clamp(yi, 0.0, side - 1)));
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
  }
  static dvec2 texel_point(uint32_t x, uint32_t y, uint32_t side) {
    return dvec2((x + 0.5) / side * 2.0 - 1.0, (y + 0.5) / side * 2.0 - 1.0);
  }
  // Prefiltered level `mip` of `array` (slot kSlot) against GGX's prefilter of `capture` converged
  // in double, at 256 texels spread over both hemispheres: RMSE relative to the reference's RMS.
  // With `reference_samples` below the converged count, the double prefilter at that count is
  // measured instead of the array (how far accuracy.md's 1024-sample reference is itself).
  static double prefilter_rmse(const reference::ProbeCapture& capture, const std::vector<uint8_t>& array, uint32_t mip,
                               uint32_t reference_samples = kReferenceSamples) {
    const uint32_t side = mip_size(kArraySide, mip);
    const double roughness = double(mip) / (kMips - 1);
    double squares = 0, signal = 0;
    for (uint32_t k = 0; k < 256; ++k) {
      const uint32_t h = k % 2, x = (k * 37 + mip) % side, y = (k * 53 + 3 * mip) % side;
      const dvec3 d = paraboloid_direction(h, texel_point(x, y, side));
      const dvec3 expected = reference::prefiltered(capture.level0, d, roughness, kReferenceSamples);
      const dvec3 got = reference_samples == kReferenceSamples
                            ? texel(array, mip, 2 * kSlot + h, x, y)
                            : reference::prefiltered(capture.level0, d, roughness, reference_samples);
      squares += glm::dot(got - expected, got - expected);
      signal += glm::dot(expected, expected);
    }
    return std::sqrt(squares / signal);
  }
};

TEST(ProbeParaboloid, RoundTripsEachTexelCentreWithinHalfATexel) {
  double worst = 0;
  for (uint32_t h = 0; h < 2; ++h)
    for (uint32_t y = 0; y < kArraySide; ++y)
      for (uint32_t x = 0; x < kArraySide; ++x) {
        const dvec2 p((x + 0.5) / kArraySide * 2.0 - 1.0, (y + 0.5) / kArraySide * 2.0 - 1.0);
        if (glm::dot(p, p) > 1.0) continue;  // past the rim: the other hemisphere's directions
        const dvec3 d = paraboloid_direction(h, p);
        ASSERT_NEAR(glm::length(d), 1.0, 1e-12);
        ASSERT_EQ(paraboloid_hemisphere(d), glm::dot(p, p) == 1.0 ? 0u : h);
        const dvec2 back = paraboloid_point(d);
        worst = std::max(worst, glm::length(back - p) * kArraySide / 2.0);  // in texels
      }
  std::printf("paraboloid round trip: worst %.3g texels\n", worst);
  EXPECT_LE(worst, 0.5);
}

TEST_F(ProbesArrayTest, ConvertsAndPrefiltersTheCaptureIntoItsSlotAlone) {
  const reference::ProbeCapture capture = reference::synthetic_capture(kFaceSide);
  const IsolatedRun result = convert(capture);
  ASSERT_TRUE(first_non_finite(result.execution).empty());
  const std::vector<uint8_t>& array = *result.outputs.at("probes.array");

  // Level 0: the cube along each texel's direction.
  double worst_level0 = 0, mean = 0;
  for (const dvec3& t : capture.level0.texels) mean += (t.x + t.y + t.z) / 3.0 / double(capture.level0.texels.size());
  for (uint32_t h = 0; h < 2; ++h)
    for (uint32_t y = 0; y < kArraySide; ++y)
      for (uint32_t x = 0; x < kArraySide; ++x) {
        const dvec3 expected =
            reference::sample(capture.level0, paraboloid_direction(h, texel_point(x, y, kArraySide)));
        const dvec3 got = texel(array, 0, 2 * kSlot + h, x, y);
        const double error = glm::length(got - expected) / (glm::length(expected) + 1e-3);
        worst_level0 = std::max(worst_level0, error);
      }
  std::printf("probes.convert level 0: worst relative error %.3g\n", worst_level0);
  EXPECT_LE(worst_level0, 0x1p-10 * 2);

  // The seam: the rim read from both hemispheres.
  double worst_seam = 0;
  for (int k = 0; k < 720; ++k) {
    const double phi = 2 * std::numbers::pi * (k + 0.5) / 720;
    const dvec2 uv = dvec2(std::cos(phi), std::sin(phi)) * 0.5 + 0.5;
    const dvec3 upper = bilinear(array, 0, 2 * kSlot, uv), lower = bilinear(array, 0, 2 * kSlot + 1, uv);
    const double gap = glm::length(upper - lower), bound = 0.02 * glm::length(upper + lower) / 2 + 0.01 * mean;
    worst_seam = std::max(worst_seam, gap / bound);
    EXPECT_LE(gap, bound) << "rim angle " << phi;
  }
  std::printf("probes.convert seam: worst gap %.3g of the bound\n", worst_seam);

  // The prefiltered levels, at 256 texels of each spread over both hemispheres, at the default
  // samples and at the most the pass allows.
  const IsolatedRun most_run = convert(capture, 255);
  const std::vector<uint8_t>& most = *most_run.outputs.at("probes.array");
  for (uint32_t mip = 1; mip < kMips; ++mip) {
    const double rmse = prefilter_rmse(capture, array, mip), rmse_most = prefilter_rmse(capture, most, mip);
    std::printf(
        "probes.convert mip %u (roughness %.1f): relative RMSE %.3g at 64 samples, %.3g at 255 (a 1024-sample "
        "prefilter in double: %.3g)\n",
        mip, double(mip) / (kMips - 1), rmse, rmse_most, prefilter_rmse(capture, array, mip, 1024));
    EXPECT_LE(rmse, mip < 3 ? 0.03 : 0.01) << "mip " << mip;
    EXPECT_LE(rmse_most, 0.01) << "mip " << mip;
  }

  // Every other slot as it was.
  for (uint32_t layer = 0; layer < kLayers; ++layer) {
    if (layer / 2 == kSlot) continue;
    for (uint32_t mip = 0; mip < kMips; ++mip) {
      const uint32_t side = mip_size(kArraySide, mip);
      for (uint32_t y = 0; y < side; y += 7)
        for (uint32_t x = 0; x < side; x += 7)
          ASSERT_EQ(texel(array, mip, layer, x, y), kBefore) << "layer " << layer << " mip " << mip;
    }
  }
}

// The prefilter on what the map's street probe captured on its first frame (probes.faces as the
// frame left it: neon tubes and windows up to 40, texels of the street about 0.1): at 64 samples,
// ≤ 1% from mip 3, ≤ 2.5% at mip 2 and ≤ 5% at mip 1 (measured 4.3%, 2.1%, 0.94%, 0.70%, 0.58%;
// at 255: 0.68%, 1.3%, 0.51%, 0.32%, 0.31%).
TEST_F(ProbesArrayTest, PrefiltersTheStreetProbesCapture) {
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  const Scene scene = build_map({1, 16.0, Shot::street});
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  const VersionData& faces = *frame.execution.final_version("probes.faces");
  const reference::ProbeCapture capture = reference::capture_of(*faces.bytes, faces.desc.extent, 0);
  const IsolatedRun result = convert(capture), most_run = convert(capture, 255);
  const std::vector<uint8_t>&array = *result.outputs.at("probes.array"), &most = *most_run.outputs.at("probes.array");
  for (uint32_t mip = 1; mip < kMips; ++mip) {
    const double rmse = prefilter_rmse(capture, array, mip), rmse_most = prefilter_rmse(capture, most, mip);
    std::printf(
        "street capture, mip %u: relative RMSE %.3g at 64 samples, %.3g at 255 (a 1024-sample prefilter: %.3g)\n", mip,
        rmse, rmse_most, prefilter_rmse(capture, array, mip, 1024));
    EXPECT_LE(rmse, mip == 1 ? 0.05 : mip == 2 ? 0.025 : 0.01) << "mip " << mip;
  }
}

const char* kLookupShader = R"(#version 460
#include "probes/capture_layout.glsl.h"
#include "probes/paraboloid.glsl.h"
#include "probes/reflection.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) readonly buffer Cases { vec4 cases[]; };
layout(set = 0, binding = 1) buffer Results { vec4 results[]; };
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= cases.length() / 5) return;
  vec3 position = cases[5 * i].xyz, r = cases[5 * i + 1].xyz, box_min = cases[5 * i + 2].xyz;
  vec3 box_max = cases[5 * i + 3].xyz, probe = cases[5 * i + 4].xyz;
  vec3 d = parallax_direction(position, r, box_min, box_max, probe);
  results[2 * i] = vec4(d, 0.0);
  results[2 * i + 1] = vec4(probe_texel(uint(cases[5 * i].w), d), 0.0);
}
)";

TEST_F(ProbesArrayTest, LookupMatchesARayBoxIntersectionInDouble) {
  std::mt19937 rng(7);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 8) / 16777216.0; };
  // Street-canyon boxes a few hundred metres from the camera (positions are camera-relative),
  // points inside them, probes inside or beside them.
  struct Case {
    dvec3 position, r, box_min, box_max, probe;
    uint32_t slot;
  };
  std::vector<Case> cases;
  for (int i = 0; i < 512; ++i) {
    Case c;
    const dvec3 centre(uniform(-300, 300), uniform(0, 20), uniform(-300, 300));
    const dvec3 half(uniform(2, 60), uniform(3, 30), uniform(2, 60));
    c.box_min = dvec3(glm::vec3(centre - half));
    c.box_max = dvec3(glm::vec3(centre + half));
    c.position = dvec3(glm::vec3(
        glm::mix(c.box_min, c.box_max, dvec3(uniform(0.01, 0.99), uniform(0.01, 0.99), uniform(0.01, 0.99)))));
    const double z = uniform(-1, 1), phi = uniform(0, 2 * std::numbers::pi), s = std::sqrt(1 - z * z);
    c.r = dvec3(glm::vec3(s * std::cos(phi), z, s * std::sin(phi)));
    c.probe = dvec3(glm::vec3(centre + dvec3(uniform(-5, 5), uniform(-2, 2), uniform(-5, 5))));
    c.slot = uint32_t(i) % kProbeSlots;
    cases.push_back(c);
  }
  std::vector<float> packed;
  for (const Case& c : cases)
    for (const glm::dvec4& v : {glm::dvec4(c.position, c.slot), glm::dvec4(c.r, 0), glm::dvec4(c.box_min, 0),
                                glm::dvec4(c.box_max, 0), glm::dvec4(c.probe, 0)})
      for (int k = 0; k < 4; ++k) packed.push_back(float(v[k]));
  const uint64_t bytes = cases.size() * 2 * 16;
  PassDecl pass = PassDecl("probes.lookup_test", PassType::compute)
                      .read("probes.cases", Use::storage_read)
                      .write("probes.results", Use::storage_write, BufferDecl{kinds::buffer, bytes})
                      .shader("test/probes_lookup.comp")
                      .run([&](PassContext& ctx) {
                        ctx.bind_pipeline();
                        ctx.push({Binding::storage(ctx.slot("probes.cases"), "probes.cases"),
                                  Binding::storage(ctx.slot("probes.results"), "probes.results")});
                        vkCmdDispatch(ctx.cmd(), uint32_t(cases.size() + 63) / 64, 1, 1);
                      });
  GraphSettings settings;
  settings.sinks = {"probes.results"};
  settings.readback = {"probes.results"};
  const std::vector<PassDecl> decls{pass};
  const IsolatedInput input = records_input(std::span<const float>(packed));
  CompiledGraph graph = compile_graph(decls, {{"probes.cases", input.desc}}, settings);
  ExecutionOptions options;
  options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
    return compile_glsl(path, kLookupShader, bindings);
  };
  const Execution run = execute_graph(*gpu_, *cache_, graph, {{"probes.cases", input.bytes}}, options);
  const VersionData* results = run.final_version("probes.results");
  ASSERT_TRUE(results && results->bytes);
  ASSERT_EQ(results->bytes->size(), bytes);
  double worst_angle = 0, worst_uv = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    float gpu[8];
    std::memcpy(gpu, results->bytes->data() + 32 * i, sizeof gpu);
    // The ray's exit from the box, slab by slab, in double.
    double t = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k)
      if (c.r[k] != 0.0) t = std::min(t, ((c.r[k] > 0 ? c.box_max[k] : c.box_min[k]) - c.position[k]) / c.r[k]);
    const dvec3 expected = glm::normalize(c.position + c.r * t - c.probe);
    const dvec3 got(gpu[0], gpu[1], gpu[2]);
    const double angle = std::atan2(glm::length(glm::cross(got, expected)), glm::dot(got, expected));
    worst_angle = std::max(worst_angle, angle);
    EXPECT_LE(angle, 1e-4) << "case " << i;
    // The texel coordinates of the GPU's direction, in double.
    const dvec2 uv = paraboloid_point(got) * 0.5 + 0.5;
    const double layer = 2.0 * c.slot + paraboloid_hemisphere(got);
    worst_uv = std::max({worst_uv, std::abs(gpu[4] - uv.x), std::abs(gpu[5] - uv.y)});
    EXPECT_NEAR(gpu[4], uv.x, 1e-5) << "case " << i;
    EXPECT_NEAR(gpu[5], uv.y, 1e-5) << "case " << i;
    EXPECT_EQ(gpu[6], layer) << "case " << i;
  }
  std::printf("parallax on the GPU: worst %.3g rad from double; texel coordinates within %.3g\n", worst_angle,
              worst_uv);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
