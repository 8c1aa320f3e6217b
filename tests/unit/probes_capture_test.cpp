// Each face a reflection probe captures (probes.cull, probes.gbuffer, probes.light) against the
// same view rendered by the frame's own passes: the city block with its probe, the camera put at
// the probe looking along each face (90°, 64×64, the face's size), lighting.deferred (the
// formulas the capture shares) and lighting.composite, in the same frame, which captures the
// probe (its first). The same lights on both sides: the city's local lights, every one of them
// (probes.cull's `lights` raised to all), and no sun (the capture reads the sun's shadow from
// shadow.distant, the frame from its cascades: they differ at shadow edges by design); no decals
// and no ambient occlusion (the captures have neither). The frame's camera is the face's view (plan.cpp: a camera
// facing the face), whose pixel (x, y) is the cube's texel (63 − x, y).
// Bounds: the face's G-buffer (probes.gbuffer's targets) is the frame's at 99% of its texels,
// bit for bit (the rest: where the projections, built one in float and one in double, round
// apart); its lit colour (probes.faces) within the composite's recorded contract (2⁻¹⁰ relative,
// 2⁻²⁴ absolute) at 99% of the texels of each face (measured 99.7% at least; the others, up to
// 4.7% off, are where the G-buffers differ).
#include <cmath>
#include <cstring>

#include "passes/assembly/renderer.h"
#include "passes/probes/capture_layout.h"
#include "tests/reference/ibl_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;

constexpr uint32_t kSide = 64;

glm::vec4 half4(const VersionData& v, uint32_t layer, uint32_t x, uint32_t y) {
  const FormatInfo f = *format_info(v.desc.format);
  const uint64_t offset = raw_subresource_offset(f, v.desc.extent, 0, 0, layer);
  float t[4];
  decode_texel(f, 0, std::span<const uint8_t>(v.bytes->data() + offset, v.bytes->size() - offset),
               uint64_t(y) * v.desc.extent.width + x, t);
  return {t[0], t[1], t[2], t[3]};
}

class ProbesCaptureTest : public GpuTest {};

TEST_F(ProbesCaptureTest, EachFaceIsWhatTheFramesOwnPassesRenderFromItsView) {
  Scene scene = build_city(3);
  std::erase_if(scene.lights, [](const Light& l) { return l.type == LightType::directional; });
  scene.decals.clear();
  std::erase_if(scene.instances, [&](const Instance& i) { return scene.materials.at(scene.material_of(i)).decal; });
  ASSERT_EQ(scene.probes.size(), 1u);
  ASSERT_FALSE(scene.lights.empty());
  const dvec3 probe = scene.probes[0].position;

  for (uint32_t face = 0; face < 6; ++face) {
    // The face's axes as reference::face_point lays its texels out: s to the right, t down.
    const dvec3 centre = reference::face_point(face, 0, 0);
    const dvec3 right = reference::face_point(face, 1, 0) - centre, up = centre - reference::face_point(face, 0, 1);
    Camera camera;
    camera.world = glm::dmat4(glm::dvec4(-right, 0), glm::dvec4(up, 0), glm::dvec4(-centre, 0), glm::dvec4(probe, 1));
    camera.yfov = float(std::numbers::pi / 2);
    camera.znear = 0.05f;
    RenderSettings settings;
    settings.width = settings.height = kSide;
    settings.lighting = FrameLighting::deferred;
    settings.path.motion = CameraPath::Motion::still;
    settings.camera = camera;
    settings.params["probes.cull"]["lights"] = 256;
    settings.params["ao"]["enabled"] = 0;  // the captures have no ambient occlusion
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    const VersionData* lit = frame.execution.final_version("lighting.lit");
    const VersionData* faces = frame.execution.final_version("probes.faces");
    ASSERT_TRUE(lit && faces) << "face " << face;
    ASSERT_EQ(faces->desc.extent.width, kSide);

    // The face's G-buffer is the frame's but where the two projections round apart (the camera's
    // is built from its float field of view and near plane, the face's in double): a few texels.
    for (const char* target : {"albedo", "normal", "material", "emissive", "occlusion"}) {
      const std::string name = std::string("gbuffer.") + target;
      const VersionData *framed = frame.execution.final_version(name),
                        *captured = frame.execution.final_version("probes." + name);
      ASSERT_TRUE(framed && captured) << name;
      const FormatInfo f = *format_info(framed->desc.format);
      const uint64_t offset = raw_subresource_offset(f, captured->desc.extent, 0, 0, face);
      uint32_t differ = 0;
      for (uint64_t i = 0; i < uint64_t(kSide) * kSide; ++i)
        differ +=
            !std::equal(framed->bytes->begin() + i * f.texel_bytes, framed->bytes->begin() + (i + 1) * f.texel_bytes,
                        captured->bytes->begin() + offset + i * f.texel_bytes);
      std::printf("  %s: %u texels differ\n", name.c_str(), differ);
      EXPECT_LE(differ, kSide * kSide / 100) << name << ", face " << face;
    }
    uint32_t within = 0, lit_texels = 0;
    double worst = 0;
    for (uint32_t y = 0; y < kSide; ++y)
      for (uint32_t x = 0; x < kSide; ++x) {
        const glm::vec4 a = half4(*lit, 0, x, y), b = half4(*faces, face, kSide - 1 - x, y);
        bool inside = true;
        for (int c = 0; c < 3; ++c) {
          const double bound = 0x1p-24 + 0x1p-10 * std::max(std::abs(a[c]), std::abs(b[c]));
          inside = inside && std::abs(a[c] - b[c]) <= bound;
          worst = std::max(worst, double(std::abs(a[c] - b[c]) / std::max(std::abs(a[c]), 1e-6f)));
        }
        within += inside;
        lit_texels += a.r + a.g + a.b > 0.05f;
      }
    const double share = double(within) / (kSide * kSide);
    std::printf("face %u: %.2f%% of texels within the composite's contract (worst relative %.3g)\n", face, 100 * share,
                worst);
    EXPECT_GE(share, 0.99) << "face " << face;
    // Not trivially equal: the street's lights light something in every face.
    EXPECT_GT(lit_texels, kSide * kSide / 20) << "face " << face;
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
