// Camera-relative rendering: the city block moved 8 km from the origin (camera, lights and all)
// renders the same G-buffer as at the origin. Stated tolerance: albedo, material and stencil
// identical; normals within one 10-bit code; depth within 2⁻²⁰ relative. The stencil holds only
// the material classes of frame.md.
#include <cmath>
#include <cstring>
#include <set>

#include "passes/frame/renderer.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {

const VersionData& output(const RenderedFrame& frame, const std::string& pass, const std::string& resource) {
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass)
      for (int v : frame.execution.passes[i].outputs)
        if (frame.execution.versions[v].resource == resource) return frame.execution.versions[v];
  throw std::runtime_error(pass + " wrote no " + resource);
}

Scene moved(Scene scene, const glm::dvec3& offset) {
  for (Instance& instance : scene.instances) instance.world[3] += glm::dvec4(offset, 0.0);
  for (Light& light : scene.lights) {
    light.position += offset;
    light.end += offset;
  }
  if (scene.camera) scene.camera->world[3] += glm::dvec4(offset, 0.0);
  return scene;
}

class FarFromOrigin : public GpuTest {};

TEST_F(FarFromOrigin, EightKilometresOutTheGBufferIsTheSame) {
  const Scene near = build_city(3);
  const Scene far = moved(near, {8000.0, 0.0, -8000.0});
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  Renderer near_renderer(*gpu_, near, settings), far_renderer(*gpu_, far, settings);
  const RenderedFrame a = near_renderer.render_frame(0, true);
  const RenderedFrame b = far_renderer.render_frame(0, true);

  for (const char* exact : {"gbuffer.albedo", "gbuffer.material"})
    EXPECT_EQ(*output(a, "gbuffer.opaque", exact).bytes, *output(b, "gbuffer.opaque", exact).bytes) << exact;

  const auto& na = *output(a, "gbuffer.opaque", "gbuffer.normal").bytes;
  const auto& nb = *output(b, "gbuffer.opaque", "gbuffer.normal").bytes;
  int worst_code = 0;
  for (size_t i = 0; i < na.size(); i += 4) {
    uint32_t wa, wb;
    std::memcpy(&wa, na.data() + i, 4);
    std::memcpy(&wb, nb.data() + i, 4);
    for (int c = 0; c < 3; ++c)
      worst_code = std::max(worst_code, std::abs(int((wa >> (10 * c)) & 1023) - int((wb >> (10 * c)) & 1023)));
  }
  EXPECT_LE(worst_code, 1);

  const VersionData& da = output(a, "gbuffer.opaque", "scene.depth");
  const VersionData& db = output(b, "gbuffer.opaque", "scene.depth");
  const size_t texels = size_t(settings.width) * settings.height;
  double worst_depth = 0;
  std::set<int> classes;
  size_t covered = 0;
  for (size_t i = 0; i < texels; ++i) {
    float za, zb;
    std::memcpy(&za, da.bytes->data() + 4 * i, 4);
    std::memcpy(&zb, db.bytes->data() + 4 * i, 4);
    if (za > 0) {
      ++covered;
      worst_depth = std::max(worst_depth, std::abs(double(za) - zb) / za);
    }
    const uint8_t sa = (*da.bytes)[4 * texels + i], sb = (*db.bytes)[4 * texels + i];
    EXPECT_EQ(sa, sb);
    classes.insert(sa);
  }
  EXPECT_GT(covered, texels / 4);
  EXPECT_LE(worst_depth, std::ldexp(1.0, -20));
  const std::set<int> allowed = {0x00, 0x02, 0x08, 0x0A, 0x15, 0x35, 0x40, 0x42, 0x95, 0xA0};
  for (int c : classes) EXPECT_TRUE(allowed.count(c)) << "stencil value " << c;
  EXPECT_TRUE(classes.count(0x08)) << "no road pixels tagged";
  std::printf("8 km offset: max depth rel diff %.3g, max normal code diff %d, stencil classes %zu\n", worst_depth,
              worst_code, classes.size());
}

}  // namespace
}  // namespace nightcap::test
