// lighting.tiled on real renders, run again in isolation on the inputs the frame recorded for it,
// against the CPU double-precision reference of tests/reference/lighting_reference.h evaluated at
// sampled pixels from the decoded inputs (10-bit normal and albedo, 8-bit material, the position
// the float depth and inverse view-projection define) over every light of frame.lights, so a
// light missing from a froxel's list shows as an error.
//
// Bounds asserted:
// - sun, point and spot lights (tubes' intensity set to 0), on the built-in city and the 2 km
//   map's street shot (271 local lights), 1280×720: as lighting_deferred_test.cpp and
//   accuracy.md, |gpu − ref| ≤ 2⁻¹⁰·ref where ref > 2⁻¹⁴, ≤ 2⁻²⁴ below; where the float inputs
//   alone move the reference by more than a quarter of that (4 ulps of position or normal), the
//   bound plus that spread.
// - the same inputs through lighting.deferred: identical bytes (both evaluate brdf.glsl in the
//   same order; lavapipe compiles both alike).
// - tubes alone (everything else at 0; radius 0, so both see the same line), on the city: diffuse
//   within 2⁻⁸ relative of the adaptive integral where it exceeds 2⁻¹⁴ (8-point Gauss–Legendre
//   of a smooth integrand and half-float storage); specular against the reference's adaptive
//   integral of GGX along the segment, per roughness × view bin (views ≤ 80°, values above
//   2⁻¹⁴): the error weighted by the reference and the worst relative error each within the
//   bin's bound in kTubeSpecular, about 15% above what was measured; a bin without a bound must
//   stay empty. The table of measured values is printed and stands by the bounds. No bin
//   reaches accuracy.md's 5% mean / 15% max, a bound for a light centred on the lobe's mirror
//   direction (ltc_test.cpp checks it there): here lights reach surfaces far off the peak, where
//   the fitted LTC lobe is zero (the GPU writes 0: worst 100%) or small while GGX's tail is not.
//   Measured: roughness [0.25, 0.5) 5.5% (worst 5.9%) at views 0-40°; [0.5, 0.75) 6.2-22.7%
//   (59-118%); [0.75, 1] 97.9% (100%).
// - spheres alone (the city's point lights with a radius of 0.25 m), on the city: diffuse within
//   2⁻⁸ of the integral over the sphere's cap; specular per bin as the tubes', within
//   kSphereSpecular: measured 11.6-92.0% weighted, worst up to 809% at views 70-80° (the LTC
//   overshoots GGX's tail there) and 100% where the GPU writes 0.
// - other froxel shapes (lights.cluster's tile_size and slices, which the pass reads from
//   lights.cluster_stats): the city and the 2 km map's street shot, whole frames, with tiles of
//   16 px and 32 slices and with 64 px and 128 slices: the same bytes as the default shape's.
// - stress: 10 000 extra lights in view, a light touching the ground, a zero-length tube, a
//   sphere light, lights at the camera: every output finite, and the pass run again from its
//   recorded inputs writes the same bytes (what replay --verify checks).
// (Over 600 lines: every case is lighting.tiled against the one reference, sharing its fixtures.)
#include <algorithm>
#include <array>
#include <cstring>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <tuple>

#include "passes/frame/gpu_types.h"
#include "passes/lighting/stage.h"
#include "passes/lighting/tiled_layout.h"
#include "tests/reference/lighting_reference.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/recorded_pass.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace ref = nightcap::reference;
using glm::dvec3;

const double kRelative = 0x1p-10, kThreshold = 0x1p-14, kAbsolute = 0x1p-24, kMaxHalf = 65504;
const double kMinRoughness = double(0.03f);  // the default floor, as the pass receives it
// The references of the BRDF have no contact shadow; SunContactShadow* checks it apart.
const ParamValues kNoContact = {{"contact_steps", 0}};

using Inputs = std::map<std::string, IsolatedInput>;

template <typename T>
std::vector<T> records(const std::vector<uint8_t>& bytes, size_t count) {
  std::vector<T> out(count);
  std::memcpy(out.data(), bytes.data(), std::min(bytes.size(), count * sizeof(T)));
  return out;
}

template <typename T>
IsolatedInput buffer(const std::vector<T>& values) {
  IsolatedInput input;
  input.desc.is_buffer = true;
  input.desc.kind = kinds::buffer;
  input.desc.buffer_size = std::max<size_t>(values.size() * sizeof(T), 16);
  auto bytes = std::make_shared<std::vector<uint8_t>>(input.desc.buffer_size, 0);
  std::memcpy(bytes->data(), values.data(), values.size() * sizeof(T));
  input.bytes = bytes;
  return input;
}

// The G-buffer, constants, camera and lights a lighting pass reads, decoded.
struct Frame {
  uint32_t width = 0, height = 0;
  GpuFrameConstants constants{};
  GpuView camera{};
  std::vector<GpuLight> lights;
  std::vector<uint32_t> albedo, normal;
  std::vector<uint8_t> material;
  std::vector<float> depth;

  size_t index(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
  bool shaded(size_t i) const { return depth[i] > 0 && (albedo[i] >> 30) == 0; }
  ref::Surface surface(uint32_t x, uint32_t y) const {
    const size_t i = index(x, y);
    return ref::make_surface(ref::reconstruct_position(camera, x, y, depth[i]), normal[i], albedo[i], &material[4 * i],
                             kMinRoughness);
  }
};

Frame decode(const Inputs& in) {
  Frame f;
  const ImageExtent extent = in.at("gbuffer.albedo").desc.extent;
  f.width = extent.width;
  f.height = extent.height;
  const size_t n = size_t(f.width) * f.height;
  std::memcpy(&f.constants, in.at("frame.constants").bytes->data(), sizeof(f.constants));
  std::memcpy(&f.camera, in.at("frame.views").bytes->data(), sizeof(f.camera));
  f.lights = records<GpuLight>(*in.at("frame.lights").bytes, f.constants.counts.x);
  f.albedo = records<uint32_t>(*in.at("gbuffer.albedo").bytes, n);
  f.normal = records<uint32_t>(*in.at("gbuffer.normal").bytes, n);
  f.material = records<uint8_t>(*in.at("gbuffer.material").bytes, 4 * n);
  f.depth = records<float>(*in.at("scene.depth").bytes, n);  // the depth plane comes first
  return f;
}

// The inputs with another light list (same length: the froxel lists index it) or constants.
Inputs with_lights(Inputs in, const std::vector<GpuLight>& lights) {
  in["frame.lights"] = buffer(lights);
  return in;
}

Inputs with_constants(Inputs in, const GpuFrameConstants& constants) {
  in["frame.constants"] = buffer(std::vector<GpuFrameConstants>{constants});
  return in;
}

struct Output {
  std::vector<float> diffuse, specular;  // RGBA per pixel
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> bytes;
  std::string non_finite;
};

std::vector<float> halves(const std::vector<uint8_t>& raw) {
  std::vector<float> out(raw.size() / 2);
  for (size_t k = 0; k < out.size(); ++k) {
    uint16_t code;
    std::memcpy(&code, raw.data() + 2 * k, 2);
    out[k] = half_to_float(code);
  }
  return out;
}

bool is_tube(const GpuLight& l) { return uint32_t(l.position_type.w) == uint32_t(LightType::tube); }

// Sun, directional, point and spot lights in double precision (tubes are left out).
ref::Shade punctual_reference(const Frame& f, const ref::Surface& s) {
  ref::Shade total;
  auto add = [&](const ref::Shade& shade) {
    total.diffuse += shade.diffuse;
    total.specular += shade.specular;
  };
  if (f.constants.sun_direction.w > 0)
    add(ref::shade_directional(s, dvec3(glm::vec3(f.constants.sun_direction)),
                               dvec3(glm::vec3(f.constants.sun_radiance))));
  for (const GpuLight& light : f.lights) {
    const uint32_t type = uint32_t(light.position_type.w);
    if (type == uint32_t(LightType::directional))
      add(ref::shade_directional(s, dvec3(glm::vec3(light.direction_cos_outer)), dvec3(glm::vec3(light.color_range))));
    else if (type != uint32_t(LightType::tube))
      add(ref::shade_punctual(s, light, 1.0));
  }
  return total;
}

// Errors of one output in units of their bound: `strict` where the float inputs move the
// reference by at most a quarter of the bound, `conditioned` (against bound + spread) elsewhere.
struct Errors {
  size_t values = 0, conditioned_values = 0;
  double strict = 0, conditioned = 0, relative = 0, absolute = 0;
  std::string where_strict, where_conditioned;
};

std::string describe(const Frame& f, const ref::Surface& s, uint32_t x, uint32_t y, int channel) {
  const size_t i = f.index(x, y);
  std::ostringstream out;
  out << "pixel " << x << "," << y << " channel " << channel << " n.v " << glm::dot(s.n, s.v) << " roughness code "
      << int(f.material[4 * i + 1]) << " metallic code " << int(f.material[4 * i]) << " distance "
      << glm::length(s.position);
  return out.str();
}

// Every `stride`-th pixel of each `stride`-th row (sky and unlit ones against black).
void compare_punctual(const Frame& f, const Output& out, uint32_t stride, Errors& diffuse, Errors& specular) {
  for (uint32_t y = stride / 2; y < f.height; y += stride)
    for (uint32_t x = stride / 2; x < f.width; x += stride) {
      const size_t i = f.index(x, y);
      const bool lit = f.shaded(i);
      const ref::Surface s = lit ? f.surface(x, y) : ref::Surface{};
      const ref::Shade shade = lit ? punctual_reference(f, s) : ref::Shade{};
      std::optional<ref::Shade> moved;
      for (int part = 0; part < 2; ++part)
        for (int c = 0; c < 3; ++c) {
          Errors& e = part ? specular : diffuse;
          const double reference = part ? shade.specular[c] : shade.diffuse[c];
          const double gpu = (part ? out.specular : out.diffuse)[4 * i + c];
          const double expected = std::min(reference, kMaxHalf), error = std::abs(gpu - expected);
          const bool relative = reference > kThreshold;
          const double bound = relative ? kRelative * expected : kAbsolute;
          ++e.values;
          if (error <= bound) {
            if (relative)
              e.relative = std::max(e.relative, error / expected);
            else
              e.absolute = std::max(e.absolute, error);
            continue;
          }
          if (!moved)
            moved = lit ? ref::input_spread(s, [&](const ref::Surface& x) { return punctual_reference(f, x); })
                        : ref::Shade{};
          const double allowance = part ? moved->specular[c] : moved->diffuse[c];
          const std::string where = describe(f, s, x, y, c) + " gpu " + std::to_string(gpu) + " ref " +
                                    std::to_string(reference) + " spread " + std::to_string(allowance);
          if (allowance <= 0.25 * std::max(kRelative * reference, kAbsolute)) {
            if (error / bound > e.strict) {
              e.strict = error / bound;
              e.where_strict = where;
            }
          } else {
            ++e.conditioned_values;
            if (error / (bound + allowance) > e.conditioned) {
              e.conditioned = error / (bound + allowance);
              e.where_conditioned = where;
            }
          }
        }
    }
}

void report(const char* scene, const char* output, const Errors& e) {
  std::printf(
      "%-8s %-8s %7zu values: within 2^-10 relative: max %.3g, below 2^-14: max abs %.3g | worst beyond: %.3g of "
      "the bound | %zu ill-conditioned: worst %.3g of bound + spread\n",
      scene, output, e.values, e.relative, e.absolute, e.strict, e.conditioned_values, e.conditioned);
}

class LightingTiled : public GpuTest {
 protected:
  static Output shade(const PassDecl& pass, const Inputs& in, ParamValues params = {}) {
    const ImageExtent extent = in.at("gbuffer.albedo").desc.extent;
    const IsolatedRun run = GpuTest::run(pass, in, extent.width, extent.height, params);
    Output out;
    out.diffuse = halves(*run.outputs.at("lighting.diffuse"));
    out.specular = halves(*run.outputs.at("lighting.specular"));
    out.bytes = run.outputs;
    out.non_finite = first_non_finite(run.execution);
    return out;
  }

  // lighting.tiled's inputs in frame 0 of `scene` at 1280×720 (or `size`), captured.
  static RecordedPass render(const Scene& scene, uint32_t width = 1280, uint32_t height = 720,
                             const std::function<void(RenderSettings&)>& adjust = {}) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.sinks = {"lighting.diffuse", "lighting.specular"};
    // The references light the sun unshadowed: shadow.sun stays 1 (tests/unit/shadow_test.cpp
    // holds the sun's shadow to its own reference).
    settings.params["shadow.sun_resolve"]["enabled"] = 0;
    // Local lights unshadowed likewise (tests/unit/shadow_local_test.cpp holds the spot lights'
    // shadows to theirs).
    settings.params["shadow.local_plan"]["max_maps"] = 0;
    if (adjust) adjust(settings);
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    EXPECT_EQ(first_non_finite(frame.execution), "");
    RecordedPass r = recorded_pass(frame, "lighting.tiled");
    EXPECT_FALSE(r.inputs.empty()) << "lighting.tiled did not run";
    return r;
  }

  // Sun, point and spot lights (tubes dark) against the reference.
  static void expect_punctual_matches(const char* name, const RecordedPass& r, uint32_t stride) {
    std::vector<GpuLight> lights = decode(r.inputs).lights;
    size_t local = 0;
    for (GpuLight& l : lights) {
      if (is_tube(l)) l.color_range = glm::vec4(0, 0, 0, l.color_range.w);
      local += uint32_t(l.position_type.w) != uint32_t(LightType::directional);
    }
    const Inputs in = with_lights(r.inputs, lights);
    const Frame f = decode(in);
    const Output out = shade(lighting_tiled_pass(), in, kNoContact);
    EXPECT_EQ(out.non_finite, "");
    Errors diffuse, specular;
    compare_punctual(f, out, stride, diffuse, specular);
    std::printf("%s: %zu local lights in frame.lights\n", name, local);
    report(name, "diffuse", diffuse);
    report(name, "specular", specular);
    EXPECT_LE(diffuse.strict, 1.0) << diffuse.where_strict;
    EXPECT_LE(specular.strict, 1.0) << specular.where_strict;
    EXPECT_LE(diffuse.conditioned, 1.0) << diffuse.where_conditioned;
    EXPECT_LE(specular.conditioned, 1.0) << specular.where_conditioned;
  }
};

Scene city() {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  return scene;
}

TEST_F(LightingTiled, CityPointSpotAndSunMatchTheReference) { expect_punctual_matches("city", render(city()), 3); }

TEST_F(LightingTiled, MapStreetShotPointSpotAndSunMatchTheReference) {
  expect_punctual_matches("2km map", render(build_map({1, 2.0, Shot::street})), 7);
}

// Point, spot and sun (no contact shadow): lighting.tiled writes what lighting.deferred writes
// from the same inputs.
TEST_F(LightingTiled, CityEqualsDeferredForPointSpotAndSun) {
  const RecordedPass r = render(city());
  std::vector<GpuLight> lights = decode(r.inputs).lights;
  for (GpuLight& l : lights)
    if (is_tube(l)) l.color_range = glm::vec4(0, 0, 0, l.color_range.w);
  const Inputs in = with_lights(r.inputs, lights);
  const Output tiled = shade(lighting_tiled_pass(), in, kNoContact), deferred = shade(lighting_deferred_pass(), in);
  size_t differing = 0, lit = 0;
  double worst = 0;
  for (size_t k = 0; k < tiled.diffuse.size(); ++k)
    for (const auto& [a, b] :
         {std::pair{tiled.diffuse[k], deferred.diffuse[k]}, {tiled.specular[k], deferred.specular[k]}}) {
      lit += b != 0;
      if (a == b) continue;
      ++differing;
      worst = std::max(worst, std::abs(double(a) - b) / std::max(double(std::abs(b)), 0x1p-24));
    }
  std::printf("tiled vs deferred on the city: %zu of %zu non-zero values differ (worst relative %.3g)\n", differing,
              lit, worst);
  EXPECT_GT(lit, 0u);
  EXPECT_EQ(differing, 0u);
}

// Every pixel's list holds every light that reaches it whatever the froxels' shape, in ascending
// order; a coarser shape adds lights that do not reach (their range window is 0, so they add 0)
// and may move a 16×16 tile to a class with more kinds of light, whose loops take a point or spot
// light with the same arithmetic. So other shapes light the frame with the same bits.
TEST_F(LightingTiled, OtherFroxelShapesLightTheSame) {
  const std::pair<const char*, Scene> scenes[] = {{"city", city()}, {"2km map", build_map({1, 2.0, Shot::street})}};
  const ParamValues shapes[] = {{{"tile_size", 16}, {"slices", 32}}, {{"tile_size", 64}, {"slices", 128}}};
  for (const auto& [name, scene] : scenes) {
    const RecordedPass base = render(scene);
    for (const ParamValues& shape : shapes) {
      const RecordedPass other =
          render(scene, 1280, 720, [&](RenderSettings& settings) { settings.params["lights.cluster"] = shape; });
      ASSERT_EQ(other.inputs.at("lights.clusters").desc.extent.depth, uint32_t(shape.at("slices")));
      for (const char* output : {"lighting.diffuse", "lighting.specular"}) {
        const std::vector<float> a = halves(*base.outputs.at(output).bytes),
                                 b = halves(*other.outputs.at(output).bytes);
        ASSERT_EQ(a.size(), b.size());
        size_t differing = 0, lit = 0;
        double worst = 0;
        for (size_t k = 0; k < a.size(); ++k) {
          lit += a[k] != 0;
          if (a[k] == b[k]) continue;
          ++differing;
          worst = std::max(worst, std::abs(double(b[k]) - a[k]) / std::max(double(std::abs(a[k])), 0x1p-24));
        }
        std::printf("%s, tiles of %d px, %d slices: %s: %zu of %zu non-zero values differ (worst relative %.3g)\n",
                    name, int(shape.at("tile_size")), int(shape.at("slices")), output, differing, lit, worst);
        EXPECT_GT(lit, 0u);
        EXPECT_EQ(differing, 0u) << name << " " << output;
      }
    }
  }
}

// Bounds on one roughness × view bin of AreaErrors: the error weighted by the reference (what a
// viewer sees of the light) and the worst relative error. nullopt: the scene has no values there.
struct BinBound {
  double weighted, worst;
};
// Rows: roughness √α in [0, 0.25), [0.25, 0.5), [0.5, 0.75), [0.75, 1]; columns: view 0-40°,
// 40-60°, 60-70°, 70-80°.
using BinBounds = std::array<std::array<std::optional<BinBound>, 4>, 4>;

// Area-light specular against its reference integral, binned by roughness and view angle, over
// values above 2⁻¹⁴ and views up to 80° (accuracy.md's domain).
class AreaErrors {
 public:
  void add(const ref::Surface& s, double gpu, double reference) {
    if (reference <= kThreshold) return;
    const double n_v = std::clamp(glm::dot(s.n, s.v), 0.0, 1.0);
    const double view = glm::degrees(std::acos(n_v));
    if (view > 80) return;
    const int r = std::min(int(std::sqrt(s.alpha) * 4), 3);
    const int v = view < 40 ? 0 : view < 60 ? 1 : view < 70 ? 2 : 3;
    const double error = std::abs(gpu - std::min(reference, kMaxHalf));
    for (Bin* bin : {&bins_[r][v], &all_}) {
      bin->error += error;
      bin->reference += reference;
      bin->worst = std::max(bin->worst, error / reference);
      ++bin->values;
    }
  }
  size_t values() const { return all_.values; }
  void print(const char* what) const {
    std::printf(
        "%s specular against the integral over the light (%zu values, views <= 80 deg): weighted %.2f%%, worst "
        "%.1f%%\n  weighted error %% (worst %%) [values] by roughness (rows) and view (columns):\n"
        "              0-40                40-60               60-70               70-80\n",
        what, all_.values, 100 * all_.weighted(), 100 * all_.worst);
    for (int r = 0; r < 4; ++r) {
      std::printf("  %-11s", kRows[r]);
      for (const Bin& bin : bins_[r])
        if (bin.values)
          std::printf(" %5.1f (%5.1f) [%4zu]", 100 * bin.weighted(), 100 * bin.worst, bin.values);
        else
          std::printf("   -                ");
      std::printf("\n");
    }
  }
  // Each bin within its bound; a bin without one must be empty, a bin with one must not.
  void expect_within(const BinBounds& bounds) const {
    for (int r = 0; r < 4; ++r)
      for (int v = 0; v < 4; ++v) {
        const Bin& bin = bins_[r][v];
        const std::string name = std::string("roughness ") + kRows[r] + ", view " + kColumns[v];
        if (!bounds[r][v]) {
          EXPECT_EQ(bin.values, 0u) << name << " has values and no bound";
          continue;
        }
        EXPECT_GT(bin.values, 0u) << name << " has a bound and no values";
        EXPECT_LE(bin.weighted(), bounds[r][v]->weighted) << name << " weighted";
        EXPECT_LE(bin.worst, bounds[r][v]->worst) << name << " worst";
      }
  }

 private:
  static constexpr const char* kRows[] = {"[0, 0.25)", "[0.25, 0.5)", "[0.5, 0.75)", "[0.75, 1]"};
  static constexpr const char* kColumns[] = {"0-40", "40-60", "60-70", "70-80"};
  struct Bin {
    double error = 0, reference = 0, worst = 0;
    size_t values = 0;
    double weighted() const { return reference > 0 ? error / reference : 0.0; }
  };
  Bin bins_[4][4], all_;
};

// What CityTubesAgainstTheSegmentIntegrals and CitySpheresAgainstTheCapIntegrals measured (the
// same on every run: lavapipe is deterministic), weighted % (worst %) [values]; the bounds sit
// about 15% above. accuracy.md's 5% mean and 15% max hold in no bin, and are not what these
// scenes can show: that bound is for a light centred on the lobe's mirror direction, which
// ltc_test.cpp checks. The city's lights reach most surfaces far off the peak, where the fitted
// LTC lobe is zero or small while GGX's tail is not: a worst of 100% is the GPU's specular
// exactly 0 with the light in range, above the horizon and lit diffusely (ltc_sphere and
// ltc_line clip the light to the LTC lobe's horizon in cosine space). The sphere's grazing bins
// (70-80°) also overshoot the tail, by up to 9×.
//
// Tubes:       0-40                40-60               60-70               70-80
// [0.25, 0.5)  5.5 (5.9) [6]
// [0.5, 0.75)  9.2 (117.9) [1328]  6.2 (74.0) [572]    22.7 (59.4) [145]   10.9 (100.0) [1255]
// [0.75, 1]    97.9 (100.0) [6]
const BinBounds kTubeSpecular = {{
    {},
    {BinBound{0.065, 0.07}, {}, {}, {}},
    {BinBound{0.11, 1.30}, BinBound{0.075, 0.85}, BinBound{0.26, 0.70}, BinBound{0.13, 1.10}},
    {BinBound{1.05, 1.10}, {}, {}, {}},
}};
// Spheres:     0-40                40-60               60-70               70-80
// [0.25, 0.5)  92.0 (100.0) [16]                       12.4 (87.8) [333]   19.3 (452.8) [809]
// [0.5, 0.75)  21.3 (100.0) [2638] 28.7 (59.7) [349]   11.6 (77.7) [1395]  26.5 (809.0) [3255]
// [0.75, 1]    15.9 (29.4) [12]
const BinBounds kSphereSpecular = {{
    {},
    {BinBound{1.00, 1.10}, {}, BinBound{0.145, 1.00}, BinBound{0.22, 5.00}},
    {BinBound{0.24, 1.10}, BinBound{0.33, 0.70}, BinBound{0.135, 0.90}, BinBound{0.30, 9.00}},
    {BinBound{0.185, 0.34}, {}, {}, {}},
}};

// Tubes alone against the reference's integrals along each segment. accuracy.md's tube bound
// (5% mean, 15% max) is met by the table where the bound is defined, a tube centred on the
// mirror direction (ltc_test.cpp); across a street the tubes also light surfaces from far off
// the lobe's peak, where the LTC's tail is not GGX's. What this asserts is what was measured,
// with a margin, bin by bin (kTubeSpecular).
TEST_F(LightingTiled, CityTubesAgainstTheSegmentIntegrals) {
  const RecordedPass r = render(city());
  Frame f = decode(r.inputs);
  std::vector<GpuLight> lights = f.lights;
  size_t tubes = 0;
  for (GpuLight& l : lights) {
    if (is_tube(l)) {
      l.end_radius.w = 0;  // a line, as the reference integrates
      ++tubes;
    } else {
      l.color_range = glm::vec4(0, 0, 0, l.color_range.w);
    }
  }
  ASSERT_GT(tubes, 0u);
  GpuFrameConstants constants = f.constants;
  constants.sun_direction.w = 0;
  const Inputs in = with_constants(with_lights(r.inputs, lights), constants);
  f = decode(in);
  const Output out = shade(lighting_tiled_pass(), in);
  EXPECT_EQ(out.non_finite, "");

  double diffuse_worst = 0;
  std::string where_diffuse;
  AreaErrors specular;
  for (uint32_t y = 5; y < f.height; y += 17)
    for (uint32_t x = 5; x < f.width; x += 17) {
      const size_t i = f.index(x, y);
      if (!f.shaded(i)) continue;
      const ref::Surface s = f.surface(x, y);
      dvec3 diffuse(0.0), spec(0.0);
      for (const GpuLight& l : f.lights) {
        if (!is_tube(l)) continue;
        const ref::Tube tube(s, l, 1.0);
        diffuse += tube.diffuse();
        spec += tube.specular();
      }
      for (int c = 0; c < 3; ++c) {
        specular.add(s, out.specular[4 * i + c], spec[c]);
        if (diffuse[c] <= kThreshold) continue;
        const double e = std::abs(out.diffuse[4 * i + c] - std::min(diffuse[c], kMaxHalf)) / diffuse[c];
        if (e > diffuse_worst) {
          diffuse_worst = e;
          where_diffuse = describe(f, s, x, y, c) + " gpu " + std::to_string(out.diffuse[4 * i + c]) + " ref " +
                          std::to_string(diffuse[c]);
        }
      }
    }
  std::printf("city tubes (%zu): diffuse max relative %.3g\n", tubes, diffuse_worst);
  specular.print("city tubes");
  ASSERT_GT(specular.values(), 1000u);
  EXPECT_LE(diffuse_worst, 0x1p-8) << where_diffuse;
  specular.expect_within(kTubeSpecular);
}

// Lambert's and GGX's integrals over the cap a sphere of unit radiance covers, seen from s (the
// sphere's centre at offset `centre`): a midpoint rule in the polar angle about the centre and
// the azimuth, the polar step an eighth of α or finer so a smooth surface's lobe is resolved.
// Empty when the point is inside the sphere or the lobe would need more than 512 steps.
struct CapIntegral {
  double lambert;  // ∫ max(n·l, 0)/π dω
  glm::dvec2 ggx;  // ∫ ggx_cos_parts dω
};

std::optional<CapIntegral> cap_integral(const ref::Surface& s, const dvec3& centre, double radius) {
  const double distance = glm::length(centre);
  if (distance <= radius) return std::nullopt;
  const double cap = std::asin(radius / distance);
  const int steps = int(std::ceil(std::max(48.0, 8 * cap / s.alpha)));
  if (steps > 512) return std::nullopt;
  const dvec3 axis = centre / distance;
  const dvec3 e1 = glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  const dvec3 e2 = glm::cross(axis, e1);
  CapIntegral sum{0, glm::dvec2(0.0)};
  for (int i = 0; i < steps; ++i) {
    const double theta = cap * (i + 0.5) / steps;
    const double weight = std::sin(theta) * (cap / steps) * (std::numbers::pi / steps);
    for (int j = 0; j < 2 * steps; ++j) {
      const double phi = std::numbers::pi * (j + 0.5) / steps;
      const dvec3 l = std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2);
      sum.lambert += std::max(glm::dot(s.n, l), 0.0) / std::numbers::pi * weight;
      sum.ggx += ref::ggx_cos_parts(s, l) * weight;
    }
  }
  return sum;
}

// The city's point lights as spheres of 0.25 m (everything else dark) against the integrals
// over each sphere's cap. Diffuse: the closed form of the horizon-cut sphere (Snyder) to 2⁻⁸
// relative; specular (LTC): bin by bin as the tubes' are (kSphereSpecular).
TEST_F(LightingTiled, CitySpheresAgainstTheCapIntegrals) {
  // In the scene, not in the recorded list: frame.constants groups frame.lights by kind.
  Scene scene = city();
  for (Light& l : scene.lights)
    if (l.type == LightType::point) l.radius = 0.25f;
  const RecordedPass r = render(scene);
  Frame f = decode(r.inputs);
  std::vector<GpuLight> lights = f.lights;
  size_t spheres = 0;
  for (GpuLight& l : lights) {
    if (uint32_t(l.position_type.w) == uint32_t(LightType::point)) {
      EXPECT_EQ(l.end_radius.w, 0.25f);
      ++spheres;
    } else {
      l.color_range = glm::vec4(0, 0, 0, l.color_range.w);
    }
  }
  ASSERT_GT(spheres, 0u);
  GpuFrameConstants constants = f.constants;
  constants.sun_direction.w = 0;
  const Inputs in = with_constants(with_lights(r.inputs, lights), constants);
  f = decode(in);
  const Output out = shade(lighting_tiled_pass(), in);
  EXPECT_EQ(out.non_finite, "");

  double diffuse_worst = 0;
  std::string where_diffuse;
  AreaErrors specular;
  size_t unresolved = 0;
  for (uint32_t y = 4; y < f.height; y += 13)
    for (uint32_t x = 4; x < f.width; x += 13) {
      const size_t i = f.index(x, y);
      if (!f.shaded(i)) continue;
      const ref::Surface s = f.surface(x, y);
      dvec3 diffuse(0.0), spec(0.0);
      bool resolved = true;
      for (const GpuLight& l : f.lights) {
        if (uint32_t(l.position_type.w) != uint32_t(LightType::point)) continue;
        const dvec3 centre = dvec3(glm::vec3(l.position_type)) - s.position;
        const double d = glm::length(centre), range = l.color_range.w, radius = l.end_radius.w;
        if (range > 0 && d >= range) continue;
        const std::optional<CapIntegral> cap = cap_integral(s, centre, radius);
        if (!cap) {
          resolved = false;
          break;
        }
        const dvec3 radiance =
            dvec3(glm::vec3(l.color_range)) * (ref::range_window(d, range) / (std::numbers::pi * radius * radius));
        const dvec3 f0 = ref::fresnel_f0(s);
        diffuse += s.albedo * (1 - s.metallic) * cap->lambert * radiance;
        spec += (f0 * cap->ggx.x + (1.0 - f0) * cap->ggx.y) * radiance;
      }
      if (!resolved) {
        ++unresolved;
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        specular.add(s, out.specular[4 * i + c], spec[c]);
        if (diffuse[c] <= kThreshold) continue;
        const double e = std::abs(out.diffuse[4 * i + c] - std::min(diffuse[c], kMaxHalf)) / diffuse[c];
        if (e > diffuse_worst) {
          diffuse_worst = e;
          where_diffuse = describe(f, s, x, y, c) + " gpu " + std::to_string(out.diffuse[4 * i + c]) + " ref " +
                          std::to_string(diffuse[c]);
        }
      }
    }
  std::printf("city spheres (%zu, r 0.25 m): diffuse max relative %.3g; %zu pixels left out (lobe too sharp)\n",
              spheres, diffuse_worst, unresolved);
  specular.print("city spheres");
  ASSERT_GT(specular.values(), 1000u);
  EXPECT_LE(diffuse_worst, 0x1p-8) << where_diffuse;
  specular.expect_within(kSphereSpecular);
}

// The sun's contact shadow against a march of the same definition in double precision over the
// recorded depth.linear (tiled.comp, contact_shadow): the sun alone lights the city (every other
// light dark), the pass runs with and without the march, and a pixel counts as shadowed where
// the march took all of its light. The two disagree only where a float rounding moves a step
// across a texel edge or a comparison across its threshold, so at most 0.5% of lit pixels
// (measured: none). A march of 4 m must shadow more than 3 times what the default 0.5 m does.
TEST_F(LightingTiled, SunContactShadowAgreesWithADoublePrecisionMarch) {
  const RecordedPass r = render(city());
  Frame f = decode(r.inputs);
  ASSERT_GT(f.constants.sun_direction.w, 0.0f) << "the city needs a sun";
  std::vector<GpuLight> lights = f.lights;
  for (GpuLight& l : lights) l.color_range = glm::vec4(0, 0, 0, l.color_range.w);
  const Inputs in = with_lights(r.inputs, lights);
  const Output off = shade(lighting_tiled_pass(), in, kNoContact);
  const std::vector<float> linear = records<float>(*in.at("depth.linear").bytes, size_t(f.width) * f.height);
  const glm::dmat4 view_projection(f.camera.view_projection);
  const dvec3 l = -glm::normalize(dvec3(glm::vec3(f.constants.sun_direction)));
  // The defaults, and a march long enough to reach across the street's kerbs and steps.
  size_t shadowed_by_default = 0;
  for (const auto& [length, thickness, steps] : {std::tuple{0.5, 0.5, 8}, {4.0, 2.0, 16}}) {
    const Output on = shade(lighting_tiled_pass(), in,
                            {{"contact_length", length}, {"contact_thickness", thickness}, {"contact_steps", steps}});
    EXPECT_EQ(on.non_finite, "");
    auto march_occluded = [&](const dvec3& p) {
      for (int i = 1; i <= steps; ++i) {
        const glm::dvec4 clip = view_projection * glm::dvec4(p + l * (length / steps * i), 1.0);
        if (clip.w <= 0) return false;
        const double sx = (clip.x / clip.w * 0.5 + 0.5) * f.width, sy = (clip.y / clip.w * 0.5 + 0.5) * f.height;
        if (sx < 0 || sy < 0 || sx >= f.width || sy >= f.height) return false;
        const double in_front = clip.w - linear[f.index(uint32_t(sx), uint32_t(sy))];
        if (in_front > 0.5 * length / steps + 1e-3 * clip.w && in_front < thickness) return true;
      }
      return false;
    };
    size_t lit = 0, shadowed = 0, disagree = 0;
    std::string where;
    for (uint32_t y = 1; y < f.height; y += 3)
      for (uint32_t x = 1; x < f.width; x += 3) {
        const size_t i = f.index(x, y);
        if (!f.shaded(i) || !(off.diffuse[4 * i + 1] > 0)) continue;  // no sunlight to take away
        ++lit;
        const bool gpu = on.diffuse[4 * i + 1] == 0;
        EXPECT_TRUE(gpu || on.diffuse[4 * i + 1] == off.diffuse[4 * i + 1]) << "all or nothing at " << x << "," << y;
        const bool cpu = march_occluded(ref::reconstruct_position(f.camera, x, y, f.depth[i]));
        shadowed += cpu;
        if (gpu != cpu && disagree++ == 0) where = std::to_string(x) + "," + std::to_string(y);
      }
    std::printf(
        "sun contact shadow over %.1f m in %d steps: %zu of %zu sunlit pixels shadowed by the double march; "
        "%zu disagree (first %s)\n",
        length, steps, shadowed, lit, disagree, where.c_str());
    ASSERT_GT(lit, 10000u);
    EXPECT_GT(shadowed, 0u) << "the test needs contact shadows to compare";
    if (length > 1) {
      EXPECT_GT(shadowed, 3 * shadowed_by_default) << "a long march shadows more";
    } else {
      shadowed_by_default = shadowed;
    }
    EXPECT_LE(double(disagree), 0.005 * double(lit)) << "first at " << where;
  }
}

// tube_nodes takes the rules ltc.glsl has: another count is refused by name, not rounded.
TEST_F(LightingTiled, TubeNodesOtherThanItsRulesAreRefused) {
  const RecordedPass r = render(city(), 64, 36);
  for (int nodes : {2, 4, 8, 16})
    EXPECT_EQ(shade(lighting_tiled_pass(), r.inputs, {{"tube_nodes", nodes}}).non_finite, "");
  try {
    shade(lighting_tiled_pass(), r.inputs, {{"tube_nodes", 5}});
    ADD_FAILURE() << "tube_nodes 5 was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("lighting.tiled.tube_nodes = 5: enum parameter, expected one of 2, 4, 8, 16"),
              std::string::npos)
        << e.what();
  }
}

// The city with 10 000 more lights in view, a light on the ground and one 0.1 mm above it, a
// zero-length tube, a sphere light, a point light and a tube at the camera: finite everywhere,
// and the pass run again from its recorded inputs writes the same bytes.
TEST_F(LightingTiled, StressStaysFiniteAndReplaysIdentically) {
  Scene scene = city();
  RenderSettings probe;
  probe.width = 640;
  probe.height = 360;
  const Camera camera = base_camera(scene, probe);
  const dvec3 eye = dvec3(camera.world[3]), forward = -glm::normalize(dvec3(camera.world[2]));
  const dvec3 right = glm::normalize(dvec3(camera.world[0]));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 10000; ++i) {
    Light l;
    const double d = 2 + 150 * unit(rng);
    l.position = eye + forward * d + right * ((unit(rng) * 2 - 1) * 0.6 * d) + dvec3(0, (unit(rng) - 0.3) * 0.3 * d, 0);
    l.type = i % 7 == 3 ? LightType::spot : LightType::point;
    l.direction = glm::vec3(glm::normalize(forward + dvec3(0, -0.5, 0)));
    l.color = {float(unit(rng)), float(unit(rng)), float(unit(rng))};
    l.intensity = 20;
    l.range = float(1 + 10 * unit(rng));
    scene.lights.push_back(l);
  }
  const dvec3 ground = eye + forward * 6.0;
  auto point = [](dvec3 p, float range) {
    Light l;
    l.position = p;
    l.intensity = 50;
    l.range = range;
    return l;
  };
  scene.lights.push_back(point(dvec3(ground.x, 0.0, ground.z), 5));
  scene.lights.push_back(point(dvec3(ground.x + 1, 1e-4, ground.z), 5));
  Light zero = point(eye + forward * 4.0, 8);
  zero.type = LightType::tube;
  zero.end = zero.position;
  zero.radius = 0.05f;
  scene.lights.push_back(zero);
  Light sphere = point(eye + forward * 5.0 + right * 1.0, 10);
  sphere.radius = 0.3f;
  scene.lights.push_back(sphere);
  scene.lights.push_back(point(eye, 10));
  Light through = point(eye - right, 10);
  through.type = LightType::tube;
  through.end = eye + right;
  scene.lights.push_back(through);

  const RecordedPass r = render(scene, 640, 360);
  const Output again = shade(lighting_tiled_pass(), r.inputs);
  EXPECT_EQ(again.non_finite, "");
  for (const char* name : {"lighting.diffuse", "lighting.specular", "lighting.tile_classes", "lighting.tile_lists"})
    EXPECT_TRUE(*again.bytes.at(name) == *r.outputs.at(name).bytes) << name << " differs when run again";
  GpuTileClasses classes;
  std::memcpy(&classes, r.outputs.at("lighting.tile_classes").bytes->data(), sizeof classes);
  EXPECT_GT(classes.local.x + classes.tube.x + classes.sphere.x + classes.sphere_and_tube.x, 0u)
      << "tiles with local lights";
  const std::vector<GpuLight> recorded_lights = decode(r.inputs).lights;
  const size_t local = std::count_if(recorded_lights.begin(), recorded_lights.end(),
                                     [](const GpuLight& l) { return uint32_t(l.position_type.w) != 0; });
  std::printf(
      "stress: %zu local lights in frame.lights; %u directional-only, %u local, %u tube, %u sphere and %u sphere and "
      "tube tiles\n",
      local, classes.directional.x, classes.local.x, classes.tube.x, classes.sphere.x, classes.sphere_and_tube.x);
  EXPECT_GT(local, 5000u);
}

// Tiles are classified and listed in row-major order, the dispatches count them, and the
// entries past the tiles are 0. A tile's class follows from its pixels' froxel lists, decoded
// here: unlit when none is shaded; else by what the lists of its pixels hold: spheres and tubes
// (5), spheres (4), tubes (3), only point and spot lights (2), nothing (1).
TEST_F(LightingTiled, TileListsAgreeWithTheClasses) {
  Scene scene = city();
  for (size_t k = 0; k < scene.lights.size(); k += 3)
    if (scene.lights[k].type == LightType::point) scene.lights[k].radius = 0.2f;  // some spheres too
  const RecordedPass r = render(scene, 320, 180);
  const Frame f = decode(r.inputs);
  GpuTileClasses classes;
  std::memcpy(&classes, r.outputs.at("lighting.tile_classes").bytes->data(), sizeof classes);
  const auto entries = records<GpuTileEntry>(*r.outputs.at("lighting.tile_lists").bytes, kLightingTileCapacity);
  const auto clusters = records<glm::uvec2>(*r.inputs.at("lights.clusters").bytes, 10 * 6 * 64);
  const auto indices = records<uint32_t>(*r.inputs.at("lights.cluster_indices").bytes, 1u << 20);
  const std::vector<float> linear = records<float>(*r.inputs.at("depth.linear").bytes, size_t(f.width) * f.height);
  const double znear = f.camera.projection_params.x, far = 2000.0;
  const uint32_t tiles_x = (f.width + 15) / 16, tiles = tiles_x * ((f.height + 15) / 16);
  std::vector<uint32_t> lists[kLightingTileClasses + 1];
  for (uint32_t t = 0; t < tiles; ++t) {
    ASSERT_LE(entries[t].tile_class, kLightingTileClasses);
    lists[entries[t].tile_class].push_back(t);
    bool lit = false, local = false, sphere = false, tube = false;
    for (uint32_t y = (t / tiles_x) * 16; y < std::min(f.height, (t / tiles_x + 1) * 16); ++y)
      for (uint32_t x = (t % tiles_x) * 16; x < std::min(f.width, (t % tiles_x + 1) * 16); ++x) {
        if (!f.shaded(f.index(x, y))) continue;
        const double k = std::floor(std::log2(linear[f.index(x, y)] / znear) / std::log2(far / znear) * 64);
        // A pixel within a float rounding of a slice boundary may fall either side: skip it.
        const double frac = std::log2(linear[f.index(x, y)] / znear) / std::log2(far / znear) * 64 - k;
        lit = true;
        if (frac < 1e-4 || frac > 1 - 1e-4) continue;
        const uint32_t slice = uint32_t(std::clamp(k, 0.0, 63.0));
        const glm::uvec2 list = clusters[(slice * 6 + y / 32) * 10 + x / 32];
        local |= list.y > 0;
        for (uint32_t e = list.x; e < list.x + list.y; ++e) {
          tube |= indices[e] >= f.constants.light_groups.z;
          sphere |= indices[e] >= f.constants.light_groups.y && indices[e] < f.constants.light_groups.z;
        }
      }
    const uint32_t expected = sphere && tube ? 5 : sphere ? 4 : tube ? 3 : local ? 2 : lit ? 1 : 0;
    EXPECT_EQ(entries[t].tile_class, expected) << "tile " << t;
  }
  const glm::uvec4* dispatch[kLightingTileClasses] = {&classes.directional, &classes.local, &classes.tube,
                                                      &classes.sphere, &classes.sphere_and_tube};
  uint32_t first = 0;
  for (uint32_t c = 1; c <= kLightingTileClasses; ++c) {
    const bool any = !lists[c].empty();
    EXPECT_EQ(*dispatch[c - 1], glm::uvec4(lists[c].size(), any, any, first)) << "class " << c;
    first += uint32_t(lists[c].size());
  }
  EXPECT_GT(lists[2].size(), 0u);
  EXPECT_GT(lists[3].size() + lists[5].size(), 0u) << "the city's tubes";
  EXPECT_GT(lists[4].size() + lists[5].size(), 0u) << "the spheres";
  size_t at = 0;
  for (uint32_t c = 1; c <= kLightingTileClasses; ++c)
    for (uint32_t t : lists[c]) EXPECT_EQ(entries[at++].listed_tile, t);
  for (size_t k = at; k < entries.size(); ++k)
    if (entries[k].listed_tile != 0 || (k >= tiles && entries[k].tile_class != 0)) {
      ADD_FAILURE() << "entry " << k << " past the lists is not 0";
      break;
    }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
