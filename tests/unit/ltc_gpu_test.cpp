// passes/lighting/ltc.glsl on lavapipe against its double-precision twin, ltc.h: tube lights
// (both specular integrals, Lambert's line, with and without a radius), the line integral itself
// and sphere lights, over random shading points, lobes of the committed table and lights
// around, across and below the horizon.
//
// Bound: |gpu − cpu| ≤ 10⁻³ of the light's plain integral (a Fresnel-weighted part is measured
// against its plain twin: it vanishes where h meets v), plus
// - tubes: 10⁻⁷ of the tube's Lambert integral head on at the distance of its nearest point. A
//   tube all but below the horizon keeps a sliver whose integral goes as its height squared,
//   and the float rounding of the normal and the ends moves that height by ~10⁻⁷ m;
// - spheres: 4·10⁻⁶ of the lobe: the polygon's closed form sums about ten edge terms of up to
//   π/2π, each rounded by ~10 float ulps, which cancel to far less when the sphere lies in the
//   lobe's tail.
// Measured: 0.20 of the bound at worst (a sphere in the lobe's tail, 8·10⁻⁷ of the lobe off);
// tubes within 8.7·10⁻⁴ relative.
#include <cstring>
#include <random>

#include "passes/core/shader.h"
#include "passes/lighting/ltc/ltc.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

struct Case {
  dvec3 n, v, end1, end2, centre;
  double roughness, tube_radius, sphere_radius;
};

// Per case, six vec4s: n and roughness, v and the tube's radius, the tube's ends (the first with
// the sphere's radius), the sphere's centre, and the lobe's M⁻¹ (m00, m02, m20, m22).
constexpr int kCaseVec4s = 6;

constexpr double kRelative = 1e-3, kSphereAbsolute = 4e-6, kTubeAbsolute = 1e-7;

const char* kShader = R"(#version 460
const int LTC_LINE_NODES = 8;  // ltc.h's default
#include "lighting/ltc.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) readonly buffer Cases { vec4 cases[]; };
layout(set = 0, binding = 1) buffer Results { vec4 results[]; };
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= cases.length() / 6) return;
  vec4 n = cases[6 * i], v = cases[6 * i + 1], end1 = cases[6 * i + 2], end2 = cases[6 * i + 3];
  vec4 centre = cases[6 * i + 4], lobe = cases[6 * i + 5];
  mat3 frame = ltc_frame(n.xyz, v.xyz);
  vec3 view = frame * v.xyz;
  // norm 1: the tube's specular is its line integrals.
  vec3 tube = ltc_tube(lobe, 1.0, view, frame * end1.xyz, frame * end2.xyz, v.w, 0.0);
  // Magnitudes (1, 1): the sphere's integrals themselves.
  vec2 sphere = ltc_sphere(lobe, vec2(1.0), view, frame * centre.xyz, end1.w);
  results[2 * i] = vec4(tube, sphere.x);
  results[2 * i + 1] = vec4(ltc_line(lobe, view, frame * end1.xyz, frame * end2.xyz, 0.0), sphere.y, 0.0);
}
)";

class LtcGpu : public GpuTest {};

TEST_F(LtcGpu, ShaderMatchesTheCpu) {
  std::mt19937 rng(3);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 8) / 16777216.0; };
  auto direction = [&] {
    const double z = uniform(-1, 1), phi = uniform(0, 2 * std::numbers::pi), r = std::sqrt(1 - z * z);
    return dvec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  // Inputs rounded to float first: the shader gets them so, and the CPU evaluates the same.
  auto rounded = [](const dvec3& p) { return dvec3(glm::vec3(p)); };
  std::vector<Case> cases;
  for (int i = 0; i < 192; ++i) {
    Case c;
    c.n = rounded(direction());
    c.v = direction();
    if (glm::dot(c.n, c.v) < 0.05) c.v = glm::normalize(c.v + c.n * (0.05 - glm::dot(c.n, c.v) + 0.1));
    c.v = rounded(c.v);
    c.roughness = float(uniform(0.03, 1.0));
    const dvec3 middle = direction() * uniform(0.5, 5.0);
    const dvec3 along = direction() * uniform(0.05, 3.0);
    c.end1 = rounded(middle - along);
    c.end2 = rounded(middle + along);
    c.tube_radius = i % 2 ? float(uniform(0.005, 0.05)) : 0.0;
    c.centre = rounded(direction() * uniform(0.5, 5.0));
    c.sphere_radius = float(uniform(0.05, 0.4));
    cases.push_back(c);
  }
  std::vector<float> packed;
  for (const Case& c : cases) {
    const ltc::Lobe lobe = ltc::lookup(ltc::ggx_table(), c.roughness, std::clamp(glm::dot(c.n, c.v), 0.0, 1.0));
    const double values[kCaseVec4s * 4] = {c.n.x,         c.n.y,         c.n.z,         c.roughness,
                                           c.v.x,         c.v.y,         c.v.z,         c.tube_radius,
                                           c.end1.x,      c.end1.y,      c.end1.z,      c.sphere_radius,
                                           c.end2.x,      c.end2.y,      c.end2.z,      0,
                                           c.centre.x,    c.centre.y,    c.centre.z,    0,
                                           lobe.minv.m00, lobe.minv.m02, lobe.minv.m20, lobe.minv.m22};
    for (double value : values) packed.push_back(float(value));
  }
  auto input = std::make_shared<std::vector<uint8_t>>(packed.size() * sizeof(float));
  std::memcpy(input->data(), packed.data(), input->size());
  ResourceDesc input_desc;
  input_desc.is_buffer = true;
  input_desc.kind = kinds::buffer;
  input_desc.buffer_size = input->size();

  const uint64_t bytes = cases.size() * 2 * 16;
  PassDecl pass = PassDecl("ltc.test", PassType::compute)
                      .read("ltc.cases", Use::storage_read)
                      .write("ltc.results", Use::storage_write, BufferDecl{kinds::buffer, bytes})
                      .shader("test/ltc.comp")
                      .run([&](PassContext& ctx) {
                        ctx.bind_pipeline();
                        ctx.push({Binding::storage(ctx.slot("ltc.cases"), "ltc.cases"),
                                  Binding::storage(ctx.slot("ltc.results"), "ltc.results")});
                        vkCmdDispatch(ctx.cmd(), uint32_t(cases.size() + 63) / 64, 1, 1);
                      });
  GraphSettings settings;
  settings.sinks = {"ltc.results"};
  settings.readback = {"ltc.results"};
  // The graph refers to its declarations: they outlive it.
  const std::vector<PassDecl> decls{pass};
  CompiledGraph graph = compile_graph(decls, {{"ltc.cases", input_desc}}, settings);
  ExecutionOptions options;
  options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
    return compile_glsl(path, kShader, bindings);
  };
  const Execution run = execute_graph(*gpu_, *cache_, graph, {{"ltc.cases", input}}, options);
  const VersionData* results = run.final_version("ltc.results");
  ASSERT_TRUE(results && results->bytes);
  ASSERT_EQ(results->bytes->size(), bytes);

  double worst = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    float gpu[8];
    std::memcpy(gpu, results->bytes->data() + 32 * i, sizeof gpu);
    const ltc::Frame frame = ltc::shading_frame(c.n, c.v);
    const ltc::Lobe lobe = ltc::lookup(ltc::ggx_table(), c.roughness, std::clamp(glm::dot(c.n, c.v), 0.0, 1.0));
    const ltc::TubeShade tube = ltc::shade_tube(ltc::ggx_table(), c.n, c.v, c.roughness, c.end1, c.end2, c.tube_radius);
    const glm::dvec2 line =
        ltc::line_integral(lobe.minv, frame.to_local(c.v), frame.to_local(c.end1), frame.to_local(c.end2));
    const glm::dvec2 sphere =
        ltc::sphere_integral({lobe.minv, 1, 1}, frame.to_local(c.v), frame.to_local(c.centre), c.sphere_radius);
    const double expected[7] = {
        tube.specular.x / lobe.norm, tube.specular.y / lobe.norm, tube.diffuse, sphere.x, line.x, line.y, sphere.y};
    const double got[7] = {gpu[0], gpu[1], gpu[2], gpu[3], gpu[4], gpu[5], gpu[6]};
    const char* names[7] = {"tube specular", "tube Fresnel part", "tube diffuse",       "sphere",
                            "line",          "line Fresnel part", "sphere Fresnel part"};
    // Each value's plain twin, which the bound scales with, and the tube head on at the distance
    // of its nearest point, for the tubes' absolute part.
    const int plain[7] = {0, 0, 2, 3, 4, 4, 3};
    const dvec3 along = c.end2 - c.end1;
    const dvec3 nearest = c.end1 + along * std::clamp(-glm::dot(c.end1, along) / glm::dot(along, along), 0.0, 1.0);
    const double head_on = glm::length(along) / (std::numbers::pi * glm::dot(nearest, nearest));
    for (int k = 0; k < 7; ++k) {
      const bool sphere_value = plain[k] == 3;
      const double bound =
          kRelative * std::abs(expected[plain[k]]) + (sphere_value ? kSphereAbsolute : kTubeAbsolute * head_on);
      worst = std::max(worst, std::abs(got[k] - expected[k]) / bound);
      EXPECT_LE(std::abs(got[k] - expected[k]), bound)
          << "case " << i << " " << names[k] << ": cpu " << expected[k] << ", gpu " << got[k];
    }
  }
  std::printf("ltc.glsl against ltc.h: worst error %.3f of the bound\n", worst);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
