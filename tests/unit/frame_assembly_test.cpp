// The frame is wired where it is assembled: a pass goes between two stages by a change to the
// assembly alone, with no edit to the passes on either side.
#include <gtest/gtest.h>

#include <set>

#include "passes/assembly/frame_passes.h"
#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

// Each texel of the source, as it is: RGBA16F to RGBA16F through a float is exact.
constexpr const char* kCopy = R"(#version 460
layout(set = 0, binding = NC_BINDING(source)) uniform sampler2D source;
layout(location = 0) out vec4 copied;
void main() { copied = texelFetch(source, ivec2(gl_FragCoord.xy), 0); }
)";

class FrameAssembly : public test::GpuTest {};

// A copy of lighting.lit put between lighting.composite and the three passes that read its
// colour (bloom's first level, exposure and tonemap): they read the copy, and the frame's image
// is the same to the bit.
TEST_F(FrameAssembly, APassGoesBetweenTheCompositeAndItsReadersByTheAssemblyAlone) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = 160;
  settings.height = 90;

  std::vector<PassDecl> passes;
  add_scene_passes(passes);
  add_lighting_passes(passes, FrameLighting::tiled);
  passes.push_back(
      PassDecl("test.copy", PassType::graphics)
          .read("lighting.lit", Use::sampled)
          .as("source")
          .write("test.lit_copy", Use::color_attachment, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
          .fullscreen("test/copy.frag"));
  add_post_passes(passes, "test.lit_copy");
  const ShaderProvider shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
    return path == "test/copy.frag" ? compile_glsl(path, kCopy, bindings) : builtin_spirv(path, bindings);
  };

  Renderer frame(*gpu_, scene, settings);
  Renderer copied(*gpu_, scene, settings, passes, shaders);
  const RenderedFrame plain = frame.render_frame(0, false);
  const RenderedFrame with_copy = copied.render_frame(0, false);

  std::set<std::string> readers;
  for (const CompiledPass& pass : with_copy.graph.passes)
    for (const BoundUse& in : pass.inputs) {
      if (pass.decl->name != "test.copy") {
        EXPECT_NE(in.resource, "lighting.lit") << pass.decl->name << " reads the composite, not the copy";
      }
      if (in.resource == "test.lit_copy" && pass.runs) {
        readers.insert(pass.decl->name);
        ASSERT_GE(in.producer, 0);
        EXPECT_EQ(with_copy.graph.passes[in.producer].decl->name, "test.copy");
      }
    }
  EXPECT_EQ(readers, (std::set<std::string>{"bloom.level0", "exposure", "tonemap"}));

  const VersionData* a = plain.execution.final_version("final.ldr");
  const VersionData* b = with_copy.execution.final_version("final.ldr");
  ASSERT_TRUE(a && a->bytes && b && b->bytes);
  EXPECT_TRUE(*a->bytes == *b->bytes) << "the copy changed the frame's image";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
