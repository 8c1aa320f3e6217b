// lighting.deferred run in isolation on synthetic G-buffers, against the CPU double-precision
// reference of tests/reference/lighting_reference.h evaluated at every pixel from the decoded
// inputs (10-bit normal and albedo, 8-bit material, the position the float depth and inverse
// view-projection define) with the same roughness floor.
//
// Bounds asserted per channel, for diffuse and specular:
// - sun, directional, point, spot (shared/design/accuracy.md): |gpu − ref| ≤ 2⁻¹⁰·ref where
//   ref > 2⁻¹⁴, ≤ 2⁻²⁴ absolute below. Above 65504, the largest finite half, the format holds
//   nothing more: there the pass saturates and the reference is min(ref, 65504).
//   Where the float inputs alone move the reference by more than a quarter of that bound
//   (position or normal moved by 4 ulps: the terminator, grazing views, lights far nearer the
//   surface than the camera, the peak of the narrowest highlights), no float evaluation can
//   pin the result closer, and the bound there is 2⁻¹⁰·ref (or 2⁻²⁴) plus that spread; these
//   pixels are counted apart. Measured: ≤ 4.85e-4 relative and ≤ 3.05e-8 absolute (the
//   half-float rounding, 2⁻¹¹ and 2⁻²⁵) on the well-conditioned pixels; ≤ 0.40 of the bound on
//   the others.
// - tube diffuse at the default 8 samples: |gpu − ref| ≤ 2⁻¹⁰·ref + 2⁻²⁴ + S·(h/d)/64, with
//   h the sample spacing, d the distance to the nearest point of the segment and
//   S = albedo·(1 − metallic)/π·I·length/d² (the whole tube at that distance, head on). The
//   midpoint rule errs most where the sampled integrand bends sharply — the horizon, the range
//   edge, the nearest point when h > d — each costing about (h/8)·(h/d)·I/d², that is
//   S·(h/d)/64 at 8 samples. Measured ≤ 0.0143·S·(h/d) over near, far and range-clipped tubes.
// - tube specular (Karis' representative point): only finite and non-negative; its error
//   against the integral of GGX along the segment is printed (median 15-100%, worse at low
//   roughness and when the representative point falls below the horizon). Representative
//   points are known to miss accuracy.md's area-light bound; LTC will replace them.
#include <algorithm>
#include <cstring>
#include <map>
#include <random>
#include <sstream>

#include "passes/depth/kinds.h"
#include "passes/frame/gpu_types.h"
#include "passes/gbuffer/kinds.h"
#include "passes/lighting/stage.h"
#include "tests/reference/lighting_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace ref = nightcap::reference;
using glm::dvec3;

const double kRelative = std::ldexp(1.0, -10), kThreshold = std::ldexp(1.0, -14), kAbsolute = std::ldexp(1.0, -24);
const double kMaxHalf = 65504;

// std::mt19937's raw sequence is fixed by the standard; the distributions are not.
class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}
  double uniform() { return double(engine_() >> 8) * (1.0 / 16777216.0); }
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double log_range(double lo, double hi) { return lo * std::pow(hi / lo, uniform()); }
  uint32_t below(uint32_t n) { return engine_() % n; }
  dvec3 direction() {
    const double z = range(-1, 1), phi = range(0, 2 * M_PI), r = std::sqrt(1 - z * z);
    return dvec3(r * std::cos(phi), r * std::sin(phi), z);
  }

 private:
  std::mt19937 engine_;
};

uint32_t encode_unorm10x3(const dvec3& c) {
  auto code = [](double v) { return uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 1023.0)); };
  return code(c.x) | code(c.y) << 10 | code(c.z) << 20;
}

// A unit vector perpendicular to `d`.
dvec3 perpendicular(const dvec3& d, Random& random) {
  for (;;) {
    const dvec3 p = glm::cross(glm::normalize(d), random.direction());
    if (glm::length(p) > 0.1) return glm::normalize(p);
  }
}

// Unit vector at cosine `c` to `d`, at a random azimuth.
dvec3 at_cosine(const dvec3& d, double c, Random& random) {
  return c * d + std::sqrt(std::max(0.0, 1 - c * c)) * perpendicular(d, random);
}

struct Inputs {
  uint32_t width = 64, height = 64;
  GpuFrameConstants frame{};
  GpuView camera{};
  glm::dmat4 view_projection{1.0};
  std::vector<GpuLight> lights;
  std::vector<uint32_t> albedo, normal;
  std::vector<uint8_t> material;
  std::vector<float> depth;
};

// A camera at the origin looking along `forward`: reversed-Z, infinite far plane, Y down, built
// here rather than with camera_math.h (the pass reads only the inverse).
void set_camera(Inputs& in, const dvec3& forward, double yfov) {
  const double znear = 0.05, aspect = double(in.width) / in.height, f = 1 / std::tan(yfov / 2);
  const dvec3 back = -glm::normalize(forward);
  const dvec3 right = glm::normalize(glm::cross(dvec3(0, 1, 0), back)), up = glm::cross(back, right);
  glm::dmat4 view(1.0);
  for (int i = 0; i < 3; ++i) {
    view[i][0] = right[i];
    view[i][1] = up[i];
    view[i][2] = back[i];
  }
  glm::dmat4 projection(0.0);
  projection[0][0] = f / aspect;
  projection[1][1] = -f;
  projection[2][3] = -1;
  projection[3][2] = znear;
  in.view_projection = projection * view;
  in.camera.view = glm::mat4(view);
  in.camera.projection = glm::mat4(projection);
  in.camera.view_projection = glm::mat4(in.view_projection);
  in.camera.inverse_view_projection = glm::mat4(glm::inverse(in.view_projection));
  in.camera.viewport = {float(in.width), float(in.height), 1.0f / in.width, 1.0f / in.height};
  in.camera.projection_params = {float(znear), float(yfov), float(aspect), 0};
}

dvec3 pixel_ray(const Inputs& in, uint32_t x, uint32_t y) {
  const glm::dvec4 p = glm::inverse(in.view_projection) *
                       glm::dvec4((x + 0.5) / in.width * 2 - 1, (y + 0.5) / in.height * 2 - 1, 1.0, 1.0);
  return glm::normalize(dvec3(p) / p.w);
}

// Fills every pixel with a surface at distance from `target` drawn by `distance()`; a normal
// that puts it near the highlight of light from `toward(position)`, at a grazing view, at the
// terminator or anywhere; and
// roughness (a fifth at 0, under the floor) and metallic (0, 1 or between) drawn at random. Pixel
// (0,0) is sky and (1,0) unlit: both must stay black.
template <class Distance, class Toward>
void fill_surfaces(Inputs& in, Random& random, const dvec3& target, Distance distance, Toward toward) {
  const size_t count = size_t(in.width) * in.height;
  in.albedo.assign(count, 0);
  in.normal.assign(count, 0);
  in.material.assign(count * 4, 0);
  in.depth.assign(count, 0.0f);
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x) {
      const size_t i = size_t(y) * in.width + x;
      const dvec3 ray = pixel_ray(in, x, y);
      // Along the ray to a point `distance()` from the target (either root, the far one when the
      // near one is behind the camera), or to its closest approach when the ray passes farther.
      const double along = glm::dot(ray, target), wanted = distance();
      const double root = std::sqrt(std::max(0.0, wanted * wanted - (glm::dot(target, target) - along * along)));
      double t = along + (random.uniform() < 0.5 ? root : -root);
      if (t < 0.1) t = std::max(along + root, 0.1);
      const dvec3 position = ray * t;
      const glm::dvec4 clip = in.view_projection * glm::dvec4(position, 1.0);
      in.depth[i] = float(clip.z / clip.w);

      const uint8_t roughness = random.uniform() < 0.2 ? 0 : uint8_t(random.below(256));
      const double r = std::max(roughness / 255.0, 0.03), alpha = r * r;
      const dvec3 v = -glm::normalize(position), l = toward(position);
      const double kind = random.uniform();
      for (int attempt = 0;; ++attempt) {
        dvec3 n;
        if (kind < 0.3)
          n = glm::normalize(glm::normalize(l + v) + random.range(0, 4) * alpha * perpendicular(l + v, random));
        else if (kind < 0.5)
          n = at_cosine(v, random.log_range(1e-3, 0.05), random);
        else if (kind < 0.7)
          n = glm::normalize(at_cosine(l, random.log_range(1e-3, 0.05), random));
        else
          n = random.direction();
        in.normal[i] = encode_unorm10x3(n * 0.5 + 0.5);
        // The reference is compared where the stored normal faces the camera (the pass clamps
        // n·v at 1e-4 below that, a choice of its own).
        if (glm::dot(ref::decode_normal(in.normal[i]), v) >= std::ldexp(1.0, -11)) break;
        if (attempt > 100) {
          in.normal[i] = encode_unorm10x3(v * 0.5 + 0.5);
          break;
        }
      }
      in.albedo[i] = encode_unorm10x3(dvec3(random.uniform(), random.uniform(), random.uniform()));
      const double m = random.uniform();
      in.material[4 * i] = m < 0.4 ? 0 : m < 0.8 ? 255 : uint8_t(random.below(256));
      in.material[4 * i + 1] = roughness;
    }
  in.depth[0] = 0;           // sky
  in.albedo[1] |= 1u << 30;  // unlit
}

template <class T>
std::vector<uint8_t> bytes_of(const std::vector<T>& values, size_t extra = 0) {
  std::vector<uint8_t> bytes(values.size() * sizeof(T) + extra, 0);
  std::memcpy(bytes.data(), values.data(), values.size() * sizeof(T));
  return bytes;
}

struct Output {
  std::vector<float> diffuse, specular;  // RGBA per pixel
};

class LightingDeferred : public GpuTest {
 protected:
  static Output shade(const Inputs& in, ParamValues params = {}) {
    const uint32_t w = in.width, h = in.height;
    // One light even when none counts: a storage buffer cannot be empty.
    std::vector<GpuLight> lights = in.lights;
    if (lights.empty()) lights.push_back(GpuLight{});
    const IsolatedRun run = GpuTest::run(
        lighting_deferred_pass(),
        {{"frame.constants", record_input(in.frame)},
         {"frame.views", record_input(in.camera)},
         {"frame.lights", records_input<GpuLight>(lights)},
         {"gbuffer.albedo", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::colour, w, h, bytes_of(in.albedo))},
         {"gbuffer.normal", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal, w, h, bytes_of(in.normal))},
         {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::material, w, h, in.material)},
         {"scene.depth",
          image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, w, h, bytes_of(in.depth, size_t(w) * h))}},
        w, h, params);
    Output out;
    for (auto [name, target] : {std::pair{"lighting.diffuse", &out.diffuse}, {"lighting.specular", &out.specular}}) {
      const std::vector<uint8_t>& raw = *run.outputs.at(name);
      target->resize(size_t(w) * h * 4);
      for (size_t k = 0; k < target->size(); ++k) {
        uint16_t code;
        std::memcpy(&code, raw.data() + 2 * k, 2);
        (*target)[k] = half_to_float(code);
      }
    }
    return out;
  }
};

ref::Surface surface_at(const Inputs& in, uint32_t x, uint32_t y, double min_roughness) {
  const size_t i = size_t(y) * in.width + x;
  return ref::make_surface(ref::reconstruct_position(in.camera, x, y, in.depth[i]), in.normal[i], in.albedo[i],
                           &in.material[4 * i], min_roughness);
}

// The largest error in units of its bound, with where it was measured. `allowance`: what the
// reference itself moves by when its float inputs move by a few ulps (see ref::input_spread()).
struct Worst {
  double relative = 0, absolute = 0, ratio = 0;
  size_t count = 0;
  std::string where;
  template <class Context>
  void add(double gpu, double reference, double allowance, const Context& context) {
    const double expected = std::min(reference, kMaxHalf);
    const double error = std::abs(gpu - expected);
    const bool relative_region = reference > kThreshold;
    const double bound = (relative_region ? kRelative * expected : kAbsolute) + allowance;
    ++count;
    if (relative_region)
      relative = std::max(relative, error / expected);
    else
      absolute = std::max(absolute, error);
    if (!(error / bound <= ratio)) {
      ratio = error / bound;
      where = context() + " gpu " + std::to_string(gpu) + " ref " + std::to_string(reference);
    }
  }
};

const double kMinRoughness = double(0.03f);  // the default floor, as the pass receives it

ref::Shade reference_shade(const Inputs& in, const ref::Surface& s) {
  ref::Shade total;
  auto add = [&](const ref::Shade& shade) {
    total.diffuse += shade.diffuse;
    total.specular += shade.specular;
  };
  if (in.frame.sun_direction.w > 0)
    add(ref::shade_directional(s, dvec3(glm::vec3(in.frame.sun_direction)), dvec3(glm::vec3(in.frame.sun_radiance))));
  for (const GpuLight& light : in.lights) {
    const uint32_t type = uint32_t(light.position_type.w);
    if (type == 0)
      add(ref::shade_directional(s, dvec3(glm::vec3(light.direction_cos_outer)), dvec3(glm::vec3(light.color_range))));
    else if (type == 3)
      add({ref::Tube(s, light, 1.0).diffuse(), ref::Tube(s, light, 1.0).specular()});
    else
      add(ref::shade_punctual(s, light, 1.0));
  }
  return total;
}

bool shaded(const Inputs& in, size_t i) { return in.depth[i] > 0 && (in.albedo[i] >> 30) == 0; }

std::string describe(const Inputs& in, const ref::Surface& s, uint32_t x, uint32_t y, int channel) {
  const size_t i = size_t(y) * in.width + x;
  std::ostringstream out;
  out << "pixel " << x << "," << y << " channel " << channel << " n.v " << glm::dot(s.n, s.v) << " roughness code "
      << int(in.material[4 * i + 1]) << " metallic code " << int(in.material[4 * i]) << " distance "
      << glm::length(s.position);
  return out.str();
}

// Errors of one output, apart where the float inputs alone move the reference by more than a
// quarter of the bound (`conditioned`, asserted against bound + spread) and elsewhere (`strict`,
// against the bound alone).
struct Errors {
  Worst strict, conditioned;
  template <class Context>
  void add(double gpu, double reference, double spread, const Context& context) {
    if (spread <= 0.25 * std::max(kRelative * reference, kAbsolute))
      strict.add(gpu, reference, 0, context);
    else
      conditioned.add(gpu, reference, spread, context);
  }
};

// Every pixel against the reference (sky and unlit pixels against black).
void compare(const Inputs& in, const Output& out, Errors& diffuse, Errors& specular) {
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x) {
      const size_t i = size_t(y) * in.width + x;
      const ref::Surface s = surface_at(in, x, y, kMinRoughness);
      const bool lit = shaded(in, i);
      const ref::Shade shade = lit ? reference_shade(in, s) : ref::Shade{};
      const ref::Shade moved =
          lit ? ref::input_spread(s, [&](const ref::Surface& x) { return reference_shade(in, x); }) : ref::Shade{};
      for (int c = 0; c < 3; ++c) {
        auto context = [&] { return describe(in, s, x, y, c); };
        diffuse.add(out.diffuse[4 * i + c], shade.diffuse[c], moved.diffuse[c], context);
        specular.add(out.specular[4 * i + c], shade.specular[c], moved.specular[c], context);
      }
    }
}

void report(const char* name, const char* output, const Errors& e) {
  std::printf(
      "%-12s %-8s well-conditioned %5zu: max rel %.3g, max abs below 2^-14 %.3g | ill-conditioned %5zu: max rel "
      "%.3g, max error/(bound+spread) %.3g\n",
      name, output, e.strict.count, e.strict.relative, e.strict.absolute, e.conditioned.count, e.conditioned.relative,
      e.conditioned.ratio);
}

struct LightCase {
  const char* name;
  int type;                     // -1: the sun, else LightType
  double yfov, light_distance;  // the view, and how far ahead of the camera a local light sits
  double near, far;             // surface distances: to the light, or to the camera for directional light
  double intensity, range;
};

void PrintTo(const LightCase& c, std::ostream* out) { *out << c.name; }

Inputs make_inputs(const LightCase& c, uint32_t seed) {
  Inputs in;
  Random random(seed);
  const dvec3 forward = glm::normalize(dvec3(0.3, -0.2, -1));
  set_camera(in, forward, glm::radians(c.yfov));
  const dvec3 colour = dvec3(random.range(0.3, 1), random.range(0.3, 1), random.range(0.3, 1)) * c.intensity;
  auto distance = [&] { return random.log_range(c.near, c.far); };
  if (c.type <= 0) {
    const dvec3 travel = glm::normalize(dvec3(-0.4, -1, 0.3));
    if (c.type < 0) {
      in.frame.sun_direction = glm::vec4(glm::vec3(travel), 1);
      in.frame.sun_radiance = glm::vec4(glm::vec3(colour), 0);
    } else {
      GpuLight light{};
      light.direction_cos_outer = glm::vec4(glm::vec3(travel), 0);
      light.color_range = glm::vec4(glm::vec3(colour), 0);
      in.lights.push_back(light);
    }
    fill_surfaces(in, random, dvec3(0), distance, [&](const dvec3&) { return -travel; });
  } else {
    const dvec3 position = forward * c.light_distance;
    GpuLight light{};
    light.position_type = glm::vec4(glm::vec3(position), float(c.type));
    light.color_range = glm::vec4(glm::vec3(colour), float(c.range));
    // A spot aimed past the camera's axis, so pixels fall inside, across and outside its cone.
    light.direction_cos_outer =
        glm::vec4(glm::normalize(glm::vec3(forward) + glm::vec3(0.2f, 0.1f, 0)), std::cos(glm::radians(35.0f)));
    light.cos_inner.x = std::cos(glm::radians(20.0f));
    in.lights.push_back(light);
    const dvec3 stored = dvec3(glm::vec3(position));
    fill_surfaces(in, random, stored, distance, [&](const dvec3& p) { return glm::normalize(stored - p); });
  }
  in.frame.counts = {uint32_t(in.lights.size()), 0, 0, 0};
  return in;
}

class LightingDeferredPunctual : public LightingDeferred, public ::testing::WithParamInterface<LightCase> {};

TEST_P(LightingDeferredPunctual, MatchesTheDoubleReferenceWithinHalfFloatBounds) {
  const LightCase& c = GetParam();
  const Inputs in = make_inputs(c, 1234 + c.type);
  const Output out = shade(in);
  Errors diffuse, specular;
  compare(in, out, diffuse, specular);
  report(c.name, "diffuse", diffuse);
  report(c.name, "specular", specular);
  EXPECT_LE(diffuse.strict.ratio, 1.0) << "worst diffuse: " << diffuse.strict.where;
  EXPECT_LE(specular.strict.ratio, 1.0) << "worst specular: " << specular.strict.where;
  EXPECT_LE(diffuse.conditioned.ratio, 1.0) << "worst ill-conditioned diffuse: " << diffuse.conditioned.where;
  EXPECT_LE(specular.conditioned.ratio, 1.0) << "worst ill-conditioned specular: " << specular.conditioned.where;
}

INSTANTIATE_TEST_SUITE_P(Lights, LightingDeferredPunctual,
                         ::testing::Values(LightCase{"sun", -1, 60, 0, 0.5, 500, 1.0, 0},
                                           LightCase{"directional", 0, 60, 0, 0.5, 500, 0.4, 0},
                                           LightCase{"point_near", 1, 5, 3, 0.01, 0.5, 0.02, 0},
                                           LightCase{"point_far", 1, 60, 30, 5, 300, 2e3, 0},
                                           LightCase{"point_range", 1, 60, 20, 10, 40, 500, 35},
                                           LightCase{"spot_near", 2, 5, 3, 0.01, 0.5, 0.02, 0},
                                           LightCase{"spot_far", 2, 60, 30, 5, 300, 2e3, 0},
                                           LightCase{"spot_range", 2, 60, 20, 10, 40, 500, 35}),
                         [](const ::testing::TestParamInfo<LightCase>& info) { return std::string(info.param.name); });

struct TubeCase {
  const char* name;
  double yfov, light_distance, length;
  double near, far;  // surface distances to the tube's midpoint
  double intensity, range;
};

void PrintTo(const TubeCase& c, std::ostream* out) { *out << c.name; }

Inputs make_tube_inputs(const TubeCase& c, uint32_t seed) {
  Inputs in;
  Random random(seed);
  const dvec3 forward = glm::normalize(dvec3(-0.2, -0.1, -1));
  set_camera(in, forward, glm::radians(c.yfov));
  const dvec3 colour = dvec3(random.range(0.3, 1), random.range(0.3, 1), random.range(0.3, 1)) * c.intensity;
  const dvec3 middle = forward * c.light_distance, along = glm::normalize(dvec3(1, 0.3, 0.2)) * (c.length / 2);
  GpuLight light{};
  light.position_type = glm::vec4(glm::vec3(middle - along), 3.0f);
  light.end_radius = glm::vec4(glm::vec3(middle + along), 0.05f);
  light.color_range = glm::vec4(glm::vec3(colour), float(c.range));
  in.lights.push_back(light);
  in.frame.counts = {1, 0, 0, 0};
  const dvec3 a = dvec3(glm::vec3(light.position_type)), b = dvec3(glm::vec3(light.end_radius));
  fill_surfaces(
      in, random, 0.5 * (a + b), [&] { return random.log_range(c.near, c.far); },
      [&](const dvec3& p) { return glm::normalize(glm::mix(a, b, random.uniform()) - p); });
  return in;
}

class LightingDeferredTube : public LightingDeferred, public ::testing::WithParamInterface<TubeCase> {};

TEST_P(LightingDeferredTube, DiffuseWithinTheMidpointBoundSpecularFinite) {
  const TubeCase& c = GetParam();
  const Inputs in = make_tube_inputs(c, 99);
  const Output out = shade(in);
  const GpuLight& light = in.lights[0];
  const dvec3 a = dvec3(glm::vec3(light.position_type)), b = dvec3(glm::vec3(light.end_radius));
  const double samples = lighting_deferred_pass().default_params().at("tube_samples");
  const double spacing = glm::length(b - a) / samples;
  double worst_k = 0, worst_relative = 0, worst_fine = 0;
  std::string where;
  std::map<int, std::vector<double>> specular_errors;  // by quarter of the roughness range
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x) {
      const size_t i = size_t(y) * in.width + x;
      if (!shaded(in, i)) continue;
      const ref::Surface s = surface_at(in, x, y, kMinRoughness);
      const ref::Tube tube(s, light, 1.0);
      const dvec3 diffuse = tube.diffuse(), specular = tube.specular();
      const dvec3 to_a = a - s.position, ab = b - a;
      const double d = glm::length(to_a + ab * std::clamp(-glm::dot(to_a, ab) / glm::dot(ab, ab), 0.0, 1.0));
      const double ratio = spacing / d;
      const dvec3 scale =
          s.albedo * (1 - s.metallic) / M_PI * dvec3(glm::vec3(light.color_range)) * glm::length(ab) / (d * d);
      for (int ch = 0; ch < 3; ++ch) {
        const double gpu = out.diffuse[4 * i + ch], expected = std::min(diffuse[ch], kMaxHalf);
        const double excess = std::abs(gpu - expected) - kRelative * expected - kAbsolute;
        if (excess / (ratio * scale[ch]) > worst_k) {
          worst_k = excess / (ratio * scale[ch]);
          where = describe(in, s, x, y, ch) + " samples apart/distance " + std::to_string(ratio) + " gpu " +
                  std::to_string(gpu) + " ref " + std::to_string(diffuse[ch]);
        }
        if (diffuse[ch] > kThreshold) {
          const double e = std::abs(gpu - expected) / expected;
          worst_relative = std::max(worst_relative, e);
          if (ratio <= 0.125) worst_fine = std::max(worst_fine, e);
        }
        const float gpu_specular = out.specular[4 * i + ch];
        ASSERT_TRUE(std::isfinite(gpu_specular) && gpu_specular >= 0) << describe(in, s, x, y, ch);
        if (specular[ch] > kThreshold)
          specular_errors[std::min(3, in.material[4 * i + 1] / 64)].push_back(
              std::abs(gpu_specular - std::min(specular[ch], kMaxHalf)) / std::min(specular[ch], kMaxHalf));
      }
    }
  std::printf(
      "%-10s diffuse at %g samples: max (error - half-float bound)/(S·h/d) %.4f (bound %.4f); max rel %.3g, %.3g "
      "where h/d <= 1/8\n",
      c.name, samples, worst_k, 1.0 / 64, worst_relative, worst_fine);
  EXPECT_LE(worst_k, 1.0 / 64) << where;
  for (auto& [quarter, errors] : specular_errors) {
    std::sort(errors.begin(), errors.end());
    std::printf(
        "%-10s specular, roughness code %3d-%3d: %4zu values, relative error median %.3g, 90%% %.3g, max %.3g\n",
        c.name, quarter * 64, quarter * 64 + 63, errors.size(), errors[errors.size() / 2],
        errors[errors.size() * 9 / 10], errors.back());
  }
}

INSTANTIATE_TEST_SUITE_P(Tubes, LightingDeferredTube,
                         ::testing::Values(TubeCase{"tube_near", 5, 3, 0.5, 0.02, 0.5, 0.05, 0},
                                           TubeCase{"tube_far", 60, 30, 6, 3, 150, 1e3, 0},
                                           TubeCase{"tube_range", 60, 20, 4, 15, 45, 200, 40}),
                         [](const ::testing::TestParamInfo<TubeCase>& info) { return std::string(info.param.name); });

// A point and a spot light 1e-4 m off a surface and one on it, a zero-length tube and a tube
// passing 1e-4 m from it, the sun, and roughness 0 everywhere (under the default floor, and
// with no floor at all): every output finite and non-negative.
TEST_F(LightingDeferred, TouchingLightsZeroLengthTubeAndZeroRoughnessStayFinite) {
  Inputs in;
  in.width = in.height = 16;
  Random random(5);
  set_camera(in, dvec3(0, 0, -1), glm::radians(60.0));
  fill_surfaces(
      in, random, dvec3(0, 0, -2), [&] { return random.log_range(0.5, 5); },
      [&](const dvec3&) { return dvec3(0, 1, 0); });
  for (size_t i = 0; i < in.depth.size(); ++i) in.material[4 * i + 1] = 0;
  const ref::Surface s = surface_at(in, 8, 8, 0);
  const glm::vec3 above = glm::vec3(s.position + 1e-4 * s.n), on = glm::vec3(s.position);
  const glm::vec3 side = glm::vec3(perpendicular(s.n, random) * 0.5);
  auto light = [](glm::vec3 position, uint32_t type) {
    GpuLight l{};
    l.position_type = glm::vec4(position, float(type));
    l.end_radius = glm::vec4(position, 0.05f);
    l.color_range = glm::vec4(10, 10, 10, 0);
    return l;
  };
  GpuLight spot = light(above, 2);
  spot.direction_cos_outer = glm::vec4(-glm::vec3(s.n), std::cos(glm::radians(30.0f)));
  spot.cos_inner.x = std::cos(glm::radians(10.0f));
  GpuLight through = light(above - side, 3);
  through.end_radius = glm::vec4(above + side, 0.05f);
  in.lights = {light(above, 1), light(on, 1), spot, light(above, 3), through};
  in.frame.counts = {uint32_t(in.lights.size()), 0, 0, 0};
  in.frame.sun_direction = glm::vec4(glm::normalize(glm::vec3(0.3f, -1, 0.2f)), 1);
  in.frame.sun_radiance = glm::vec4(3, 3, 3, 0);
  for (const ParamValues& params : {ParamValues{}, ParamValues{{"min_roughness", 0.0}}}) {
    const Output out = shade(in, params);
    for (const std::vector<float>* values : {&out.diffuse, &out.specular})
      for (size_t k = 0; k < values->size(); ++k)
        ASSERT_TRUE(std::isfinite((*values)[k]) && (*values)[k] >= 0)
            << "texel " << k / 4 << " channel " << k % 4 << " = " << (*values)[k]
            << (params.empty() ? "" : " with min_roughness 0");
  }
}

// The reference's segment integral against the closed form for a segment parallel to the
// surface, centred above the point at height z: ∫ z/(z² + x²)^{3/2} dx = L/(z·√(z² + L²/4)).
TEST(LightingDeferredReference, TubeIntegralMatchesTheClosedForm) {
  for (double z : {1e-3, 0.05, 1.0, 30.0})
    for (double length : {1e-3, 0.5, 8.0}) {
      ref::Surface s;
      s.position = dvec3(0);
      s.n = dvec3(0, 1, 0);
      s.v = glm::normalize(dvec3(0, 1, 1));
      s.albedo = dvec3(1);
      GpuLight light{};
      light.position_type = glm::vec4(-length / 2, z, 0, 3);
      light.end_radius = glm::vec4(length / 2, z, 0, 0);
      light.color_range = glm::vec4(1, 1, 1, 0);
      const dvec3 a = dvec3(glm::vec3(light.position_type)), b = dvec3(glm::vec3(light.end_radius));
      const double l = b.x - a.x, h = a.y;  // as stored in float
      const double exact = l / (h * std::sqrt(h * h + l * l / 4)) / M_PI;
      EXPECT_NEAR(ref::Tube(s, light, 1.0).diffuse().x, exact, 1e-9 * exact) << "z " << z << " length " << length;
    }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
