// Camera-relative rendering: the city block moved 8 km from the origin (camera, lights, probes and all)
// renders the same G-buffer as at the origin. Stated tolerance: none. Every target of
// gbuffer.opaque (albedo, normal, material, emissive, motion, depth and stencil) is bit-identical:
// the offset cancels exactly in the double-precision camera-relative transforms, so the GPU sees
// the same floats. The second frame is compared, so the camera has moved and the motion vectors
// are not zero. The stencil holds only the material classes of frame.md. The probes' face views
// (probes.views) are bit-identical too.
#include <cmath>
#include <cstring>
#include <set>

#include "passes/assembly/renderer.h"
#include "tests/unit/gpu_fixture.h"
#include "tests/unit/moved_scene.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

std::map<std::string, const VersionData*> outputs(const RenderedFrame& frame, const std::string& pass) {
  std::map<std::string, const VersionData*> result;
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass)
      for (int v : frame.execution.passes[i].outputs)
        result[frame.execution.versions[v].resource] = &frame.execution.versions[v];
  return result;
}

class FarFromOrigin : public GpuTest {};

TEST_F(FarFromOrigin, EightKilometresOutEveryGBufferTargetAndProbeViewIsBitIdentical) {
  const Scene near = build_city(3);
  const Scene far = moved(near, {8000.0, 0.0, -8000.0});
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  Renderer near_renderer(*gpu_, near, settings), far_renderer(*gpu_, far, settings);
  const RenderedFrame near_frame = near_renderer.render_frame(1, true);
  const RenderedFrame far_frame = far_renderer.render_frame(1, true);
  const auto a = outputs(near_frame, "gbuffer.opaque");
  const auto b = outputs(far_frame, "gbuffer.opaque");

  const std::set<std::string> targets = {"gbuffer.albedo", "gbuffer.normal",    "gbuffer.material", "gbuffer.emissive",
                                         "gbuffer.motion", "gbuffer.occlusion", "scene.depth"};
  std::set<std::string> written;
  for (const auto& [name, version] : a) written.insert(name);
  EXPECT_EQ(written, targets);
  for (const auto& [name, version] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_EQ(*version->bytes, *b.at(name)->bytes) << name << " differs 8 km out";
  }

  // The probes' cube faces are views relative to the camera too.
  const auto near_probes = outputs(near_frame, "probes.plan"), far_probes = outputs(far_frame, "probes.plan");
  ASSERT_TRUE(near_probes.count("probes.views") && far_probes.count("probes.views"));
  EXPECT_FALSE(near_probes.at("probes.views")->bytes->empty()) << "the city's probe is captured on its first frame";
  EXPECT_EQ(*near_probes.at("probes.views")->bytes, *far_probes.at("probes.views")->bytes)
      << "probes.views differs 8 km out";

  // What is compared is not trivially equal: the camera moved, depth covers the view, and the
  // stencil carries the classes of frame.md, roads among them.
  const VersionData& motion = *a.at("gbuffer.motion");
  double largest_motion = 0;
  for (size_t i = 0; i + 2 <= motion.bytes->size(); i += 2) {
    uint16_t h;
    std::memcpy(&h, motion.bytes->data() + i, 2);
    largest_motion = std::max(largest_motion, double(std::abs(half_to_float(h))));
  }
  EXPECT_GT(largest_motion, 1e-4);
  const VersionData& depth = *a.at("scene.depth");
  const size_t texels = size_t(settings.width) * settings.height;
  size_t covered = 0;
  std::set<int> classes;
  for (size_t i = 0; i < texels; ++i) {
    float z;
    std::memcpy(&z, depth.bytes->data() + 4 * i, 4);
    covered += z > 0;
    classes.insert((*depth.bytes)[4 * texels + i]);
  }
  EXPECT_GT(covered, texels / 4);
  const std::set<int> allowed = {0x00, 0x02, 0x08, 0x0A, 0x15, 0x35, 0x40, 0x42, 0x95, 0xA0};
  for (int c : classes) EXPECT_TRUE(allowed.count(c)) << "stencil value " << c;
  EXPECT_TRUE(classes.count(0x08)) << "no road pixels tagged";
}

// The map's far corner: a small map (traffic included, so gbuffer.dynamic draws too) moved to the
// corner of a 16 km map renders the G-buffer it renders at the origin, bit for bit.
TEST_F(FarFromOrigin, AtTheMapsFarCornerEveryGBufferTargetIsBitIdentical) {
  const Scene near = build_map({1, 1.0, Shot::street});
  const Scene far = moved(near, {7500.0, 0.0, 7500.0});
  RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  Renderer near_renderer(*gpu_, near, settings), far_renderer(*gpu_, far, settings);
  near_renderer.render_frame(0, false);
  far_renderer.render_frame(0, false);
  const RenderedFrame a = near_renderer.render_frame(1, true), b = far_renderer.render_frame(1, true);
  ASSERT_GT(a.execution.final_version("draws.gbuffer.dynamic")->bytes->size(), 0u) << "no traffic in view";
  for (const char* name : {"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "gbuffer.emissive", "gbuffer.motion",
                           "gbuffer.occlusion", "scene.depth"})
    EXPECT_EQ(*a.execution.final_version(name)->bytes, *b.execution.final_version(name)->bytes)
        << name << " differs at the far corner";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
