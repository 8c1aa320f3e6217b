// shadow.topdown and the sky visibility read from it (shadow/topdown.glsl), against a CPU ray
// cast straight up in double (tests/reference/shadow_reference.h's triangles, brute force): a
// street of boxes with a bridge, an overhang and a roof over a gap, seen from 8 m up. At every
// 4th pixel of every 4th row, the surface point pushed along its normal as the lookup pushes it
// is open to the sky when the ray meets no triangle; the lookup's answer (≥ 0.5: open) agrees at
// ≥ 99% of the points away from the map's edges, those whose answer changes within 2 texels
// across (a map cannot place an edge closer than its texels). Then the plan: a still camera
// redraws the map on frame 0 alone and carries it (bit for bit) after; a camera that crosses
// an eighth of the map's side redraws it; a cut redraws it. And the map's kind, as inspect and the
// report read it.
#include <cmath>
#include <cstring>

#include "passes/assembly/renderer.h"
#include "passes/core/resource_kind.h"
#include "passes/core/shader.h"
#include "passes/scene/scene_kit.h"
#include "passes/shadow/topdown_layout.h"
#include "tests/reference/shadow_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

// A 600 m ground (its top at y = 0), a street of buildings along -z, a bridge across it at 6 m,
// a 3 m overhang off a wall at 4 m, and two towers joined by a roof over the gap between them.
Scene street_with_covers() {
  Scene scene;
  scene.source = "top-down sky visibility reference";
  scene_kit::Builder build(scene);
  const uint32_t grey = build.material(scene_kit::plain("ground", {0.5f, 0.5f, 0.5f}, 0.0f, 0.8f, stencil::plain));
  build.place(build.box(glm::vec3(300.0f, 0.5f, 300.0f), grey, 1.0f, true, true), {0.0, -0.5, 0.0});
  const std::vector<std::pair<dvec3, dvec3>> boxes = {
      {{-12.0, 10.0, -40.0}, {4.0, 10.0, 20.0}},                                        // the street's walls
      {{12.0, 7.0, -40.0}, {4.0, 7.0, 20.0}},    {{0.0, 6.5, -30.0}, {8.0, 0.5, 3.0}},  // the bridge between them
      {{-6.5, 4.2, -50.0}, {1.5, 0.2, 4.0}},                                            // an overhang off the left wall
      {{-14.0, 6.0, -80.0}, {3.0, 6.0, 3.0}},                                           // two towers
      {{-2.0, 6.0, -80.0}, {3.0, 6.0, 3.0}},     {{-8.0, 12.5, -80.0}, {9.0, 0.5, 3.0}}};  // the roof over the gap
  for (const auto& [centre, half] : boxes) build.place(build.box(glm::vec3(half), grey, 1.0f, true, true), centre);
  scene.lights.push_back(scene_kit::moon());
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  camera.znear = 0.1f;
  camera.world = glm::inverse(glm::lookAt(dvec3(0.0, 8.0, 0.0), dvec3(0.0, 0.0, -60.0), dvec3(0.0, 1.0, 0.0)));
  scene.camera = camera;
  return scene;
}

const char* kVisibilityShader = R"(#version 460
#include "shadow/topdown_layout.glsl.h"
layout(local_size_x = 64) in;
layout(std140, set = 0, binding = 0) uniform TopdownBlock { GpuTopdown topdown; };
layout(set = 0, binding = 1) uniform sampler2D topdown_map;
layout(set = 0, binding = 2) readonly buffer Cases { vec4 cases[]; };
layout(set = 0, binding = 3) buffer Results { float results[]; };
#include "shadow/topdown.glsl"
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= cases.length() / 2) return;
  results[i] = topdown_sky_visibility(cases[2 * i].xyz, cases[2 * i + 1].xyz);
}
)";

class TopdownSky : public GpuTest {
 protected:
  // topdown_sky_visibility() on the GPU at camera-relative points and normals.
  std::vector<float> visibility(const VersionData& map, const VersionData& data, const std::vector<dvec3>& points,
                                const std::vector<dvec3>& normals) {
    std::vector<float> packed;
    for (size_t i = 0; i < points.size(); ++i)
      for (const glm::dvec4& v : {glm::dvec4(points[i], 0.0), glm::dvec4(normals[i], 0.0)})
        for (int k = 0; k < 4; ++k) packed.push_back(float(v[k]));
    const uint64_t bytes = points.size() * 4;
    PassDecl pass = PassDecl("topdown.visibility_test", PassType::compute)
                        .read("shadow.topdown_data", Use::uniform_buffer)
                        .read("shadow.topdown", Use::sampled)
                        .read("topdown.cases", Use::storage_read)
                        .write("topdown.results", Use::storage_write, BufferDecl{kinds::buffer, bytes})
                        .shader("test/topdown_visibility.comp")
                        .run([&](PassContext& ctx) {
                          ctx.bind_pipeline();
                          ctx.push_declared();
                          vkCmdDispatch(ctx.cmd(), uint32_t(points.size() + 63) / 64, 1, 1);
                        });
    const IsolatedRun run =
        run_isolated(*gpu_, *cache_, pass,
                     {{"shadow.topdown_data", {data.desc, data.bytes}},
                      {"shadow.topdown", {map.desc, map.bytes}},
                      {"topdown.cases", records_input(std::span<const float>(packed))}},
                     {}, 1, 1, [](const std::string&, const std::string& path, const std::string& bindings) {
                       return compile_glsl(path, kVisibilityShader, bindings);
                     });
    std::vector<float> out(points.size());
    std::memcpy(out.data(), run.outputs.at("topdown.results")->data(), bytes);
    return out;
  }
};

TEST_F(TopdownSky, SkyVisibilityAgreesWithARayCastStraightUp) {
  const Scene scene = street_with_covers();
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.path.motion = CameraPath::Motion::still;
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);
  ASSERT_TRUE(first_non_finite(frame.execution).empty());
  const VersionData& map = *frame.execution.final_version("shadow.topdown");
  const VersionData& data_version = *frame.execution.final_version("shadow.topdown_data");
  const GpuTopdown data = host_records<GpuTopdown>(*data_version.bytes).at(0);
  const VersionData& depth = *frame.execution.final_version("scene.depth");
  const VersionData& normal = *frame.execution.final_version("gbuffer.normal");
  GpuView camera;
  std::memcpy(&camera, frame.execution.final_version("frame.views")->bytes->data(), sizeof camera);

  const dvec3 eye(frame.camera.world[3]);
  const reference::ShadowTriangles triangles(scene, eye);
  const double push = data.extent.w, texel = data.extent.x;
  const dvec3 up(0.0, 1.0, 0.0);
  auto open = [&](const dvec3& p) { return !triangles.blocked(p, up); };
  std::vector<dvec3> points, normals;
  std::vector<bool> expected, near_edge;
  const FormatInfo depth_format = *format_info(depth.desc.format), normal_format = *format_info(normal.desc.format);
  for (uint32_t y = 2; y < settings.height; y += 4)
    for (uint32_t x = 2; x < settings.width; x += 4) {
      const uint64_t i = uint64_t(y) * settings.width + x;
      float z[4], n[4];
      decode_texel(depth_format, 0, *depth.bytes, i, z);
      if (z[0] <= 0.0f) continue;
      decode_texel(normal_format, 0, *normal.bytes, i, n);
      const double nx = (x + 0.5) / settings.width * 2 - 1, ny = (y + 0.5) / settings.height * 2 - 1;
      const glm::dvec4 p = glm::dmat4(camera.inverse_view_projection) * glm::dvec4(nx, ny, z[0], 1.0);
      const dvec3 position = dvec3(p) / p.w;
      const dvec3 normal_vector = glm::normalize(dvec3(n[0], n[1], n[2]) * 2.0 - 1.0);
      const dvec3 pushed = position + normal_vector * push;
      const bool sky = open(pushed);
      bool edge = false;
      for (int k = 0; k < 8 && !edge; ++k) {
        const double angle = k * 0.7853981633974483;
        edge = open(pushed + dvec3(std::cos(angle), 0.0, std::sin(angle)) * (2.0 * texel)) != sky;
      }
      points.push_back(position);
      normals.push_back(normal_vector);
      expected.push_back(sky);
      near_edge.push_back(edge);
    }
  const std::vector<float> got = visibility(map, data_version, points, normals);
  size_t compared = 0, agreed = 0, covered = 0;
  std::string first_disagreement;
  for (size_t i = 0; i < points.size(); ++i) {
    if (near_edge[i]) continue;
    ++compared;
    covered += !expected[i];
    const bool agrees = (got[i] >= 0.5f) == expected[i];
    agreed += agrees;
    if (!agrees && first_disagreement.empty())
      first_disagreement = "point " + std::to_string(i) + ": ray " + (expected[i] ? "open" : "covered") +
                           ", visibility " + std::to_string(got[i]);
  }
  std::printf("top-down sky visibility: %zu of %zu points away from edges agree (%zu covered), %zu near edges\n",
              agreed, compared, covered, points.size() - compared);
  ASSERT_GT(compared, 1000u);
  EXPECT_GT(covered, 30u) << "the bridge, the overhang and the roof cover nothing the camera sees";
  EXPECT_GE(double(agreed) / double(compared), 0.99) << first_disagreement;
}

TopdownPlan plan_of(const RenderedFrame& frame) {
  return host_records<TopdownPlan>(*frame.execution.final_version("shadow.topdown_plan")->bytes).at(0);
}

TEST_F(TopdownSky, AStillCameraDrawsTheMapOnceAndCarriesItOver) {
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.motion = CameraPath::Motion::still;
  settings.path.cuts = {3};
  const Scene scene = street_with_covers();
  Renderer renderer(*gpu_, scene, settings);
  std::vector<uint8_t> first;
  for (uint32_t f = 0; f < 4; ++f) {
    const RenderedFrame frame = renderer.render_frame(f, true);
    const TopdownPlan plan = plan_of(frame);
    const std::vector<uint8_t>& map = *frame.execution.final_version("shadow.topdown")->bytes;
    if (f == 0) first = map;
    EXPECT_EQ(plan.refresh, uint32_t(f == 0 || f == 3 ? TopdownRefresh::no_history : TopdownRefresh::kept))
        << "frame " << f;
    EXPECT_EQ(plan.draws > 0, f == 0 || f == 3) << "frame " << f;
    EXPECT_EQ(map, first) << "frame " << f << ": the map of a still camera changed";
  }
}

// Driving 14 m/s along the map's street, a frame every 2 s (28 m): the map's centre moves by an
// eighth of its side (64 m) every few frames; between, it is carried over.
TEST_F(TopdownSky, ADrivingCameraRedrawsTheMapAsItCrossesAnEighth) {
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.path.motion = CameraPath::Motion::drive;
  const Scene scene = build_map({1, 2.0, Shot::street});
  Renderer renderer(*gpu_, scene, settings);
  uint32_t moved = 0, kept = 0;
  for (uint32_t k = 0; k < 8; ++k) {
    const TopdownPlan plan = plan_of(renderer.render_frame(120 * k, false));
    if (k == 0) {
      EXPECT_EQ(plan.refresh, uint32_t(TopdownRefresh::no_history));
      continue;
    }
    moved += plan.refresh == uint32_t(TopdownRefresh::moved);
    kept += plan.refresh == uint32_t(TopdownRefresh::kept);
    EXPECT_EQ(plan.draws > 0, plan.refresh == uint32_t(TopdownRefresh::moved)) << "frame " << 120 * k;
  }
  EXPECT_GE(moved, 2u);
  EXPECT_GE(kept, 2u);
}

// What `inspect pixel` says of a texel of the map, and how the report draws it.
TEST(TopdownKind, ATexelReadsAsTheShareOfTheHeightRangeAndDrawsByHeight) {
  const std::optional<ResourceKind> kind = kind_by_name("height_from_above");
  ASSERT_TRUE(kind);
  const KindInfo& info = kind_info(*kind);
  nlohmann::ordered_json roof, nothing;
  info.describe(TexelValues{{0.25}, {}}, KindFrame{}, roof);
  info.describe(TexelValues{{1.0}, {}}, KindFrame{}, nothing);
  EXPECT_EQ(roof["covered"], true);
  EXPECT_DOUBLE_EQ(roof["height_share"].get<double>(), 0.75);
  EXPECT_EQ(nothing["covered"], false);
  const TexelPicture picture = info.draw(TexelValues{{0.25}, {}}, KindFrame{});
  EXPECT_EQ(picture.scale, TexelPicture::Scale::relative);
  EXPECT_DOUBLE_EQ(picture.value[1], 0.75);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
