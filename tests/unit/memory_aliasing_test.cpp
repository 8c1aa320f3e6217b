// Transient memory aliasing on the GPU: a chain a -> b -> c -> d of compute passes, where a and c
// (and b and d) are never alive at the same step, so they may share bytes. The result is the
// same bit for bit with aliasing on and off and equals the values computed here, the frame
// needs less memory with it, and the validation layer (synchronization validation included)
// reports nothing: c's first use waits for a's last. The built-in city's frame, captured whole,
// is also the same with aliasing and without.
#include <cstring>

#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kSize = 64;

const char* kStep = R"(#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D source;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D target;
layout(push_constant) uniform Params { float scale, add; };
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  imageStore(target, p, vec4(texelFetch(source, p, 0).r * scale + add));
}
)";
const char* kFirst = R"(#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform writeonly image2D target;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  imageStore(target, p, vec4(float(p.x + 64 * p.y)));
}
)";

struct StepConstants {
  float scale, add;
};

ImageDecl plane() {
  ImageDecl d{VK_FORMAT_R32_SFLOAT, kinds::hdr_colour};
  d.size = {SizeRule::Mode::absolute, kSize, kSize, ""};
  return d;
}

PassDecl step(const std::string& from, const std::string& to, float scale, float add) {
  return PassDecl(to, PassType::compute)
      .read(from, Use::sampled)
      .write(to, Use::storage_write, plane())
      .shader("test/step.comp")
      .push_constants<StepConstants>()
      .run([from, to, scale, add](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push({Binding::texture(ctx.slot(from), from, ctx.nearest_clamp()), Binding::image(ctx.slot(to), to)});
        ctx.push_constants(StepConstants{scale, add});
        vkCmdDispatch(ctx.cmd(), kSize / 8, kSize / 8, 1);
      });
}

std::vector<PassDecl> chain() {
  std::vector<PassDecl> p;
  p.push_back(PassDecl("a", PassType::compute)
                  .write("a", Use::storage_write, plane())
                  .shader("test/first.comp")
                  .run([](PassContext& ctx) {
                    ctx.bind_pipeline();
                    ctx.push({Binding::image(ctx.slot("a"), "a")});
                    vkCmdDispatch(ctx.cmd(), kSize / 8, kSize / 8, 1);
                  }));
  p.push_back(step("a", "b", 2.0f, 1.0f));
  p.push_back(step("b", "c", 3.0f, 0.0f));
  p.push_back(step("c", "d", 1.0f, 7.0f));
  return p;
}

class MemoryAliasing : public GpuTest {
 protected:
  static Execution run(const std::vector<PassDecl>& decls, CompiledGraph& graph, bool alias) {
    GraphSettings settings;
    settings.sinks = {"d"};
    settings.readback = {"d"};
    graph = compile_graph(decls, {}, settings);
    ExecutionOptions options;
    options.alias_memory = alias;
    options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
      return compile_glsl(path, path == "test/first.comp" ? kFirst : kStep, bindings);
    };
    return execute_graph(*gpu_, *cache_, graph, {}, options);
  }
};

TEST_F(MemoryAliasing, ResourcesAliveApartShareMemoryAndNothingChanges) {
  const std::vector<PassDecl> decls = chain();
  CompiledGraph graph;
  const Execution aliased = run(decls, graph, true);
  EXPECT_LT(graph.lifetimes.at("a").last, graph.lifetimes.at("c").first);
  EXPECT_LT(graph.lifetimes.at("b").last, graph.lifetimes.at("d").first);
  EXPECT_GE(graph.lifetimes.at("b").last, graph.lifetimes.at("c").first) << "c is written while b is read";
  EXPECT_NE(graph.lifetimes.at("a").last_use.stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, 0u);
  for (const PlannedBarrier& b : graph.passes[2].sync.before_pass)
    EXPECT_EQ(b.first_use, b.resource == "c") << b.resource;

  const Execution apart = run(decls, graph, false);
  EXPECT_LT(aliased.memory_bytes, apart.memory_bytes);
  EXPECT_EQ(aliased.memory_bytes_without_aliasing, apart.memory_bytes);
  EXPECT_EQ(apart.memory_bytes, apart.memory_bytes_without_aliasing);
  // Two of the four images are enough (R32F 64×64: 16 KiB each, plus alignment).
  EXPECT_LE(aliased.memory_bytes, apart.memory_bytes / 2 + 4096);

  const VersionData* d = aliased.final_version("d");
  ASSERT_TRUE(d && d->bytes);
  ASSERT_TRUE(apart.final_version("d")->bytes);
  EXPECT_EQ(*d->bytes, *apart.final_version("d")->bytes);
  for (uint32_t i = 0; i < kSize * kSize; ++i) {
    float value;
    std::memcpy(&value, d->bytes->data() + 4 * i, 4);
    ASSERT_EQ(value, (float(i) * 2.0f + 1.0f) * 3.0f + 7.0f) << "texel " << i;
  }
}

TEST_F(MemoryAliasing, TheWholeFrameIsTheSameWithAndWithoutIt) {
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = 96;
  settings.height = 54;
  Renderer aliased_renderer(*gpu_, scene, settings);
  const RenderedFrame aliased = aliased_renderer.render_frame(0, true);
  settings.alias_memory = false;
  Renderer apart_renderer(*gpu_, scene, settings);
  const RenderedFrame apart = apart_renderer.render_frame(0, true);
  EXPECT_LT(aliased.execution.memory_bytes, apart.execution.memory_bytes);
  ASSERT_EQ(aliased.execution.versions.size(), apart.execution.versions.size());
  for (size_t v = 0; v < aliased.execution.versions.size(); ++v) {
    const VersionData &a = aliased.execution.versions[v], &b = apart.execution.versions[v];
    ASSERT_EQ(a.resource, b.resource);
    ASSERT_TRUE(a.bytes && b.bytes) << a.resource;
    EXPECT_TRUE(*a.bytes == *b.bytes) << "version " << v << " of " << a.resource << " differs";
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
