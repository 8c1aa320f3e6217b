// A CPU pass that reads what a GPU pass computed in the same frame: the executor submits the
// frame so far, waits, and carries on in a second command buffer; what the CPU pass writes is
// uploaded for the GPU passes after it. Checked against values computed here, with and without
// a capture (which already reads every version back), and under the validation layer.
#include <cstring>

#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kCount = 64;

const std::map<std::string, std::string> kShaders = {
    {"test/squares.comp", R"(#version 460
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Out { uint squares[]; };
void main() { squares[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x * gl_GlobalInvocationID.x; }
)"},
    {"test/offset.comp", R"(#version 460
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) readonly buffer In { uint prefix[]; };
layout(set = 0, binding = 1) buffer Out { uint result[]; };
void main() { result[gl_GlobalInvocationID.x] = prefix[gl_GlobalInvocationID.x] + 1000u; }
)"},
};

ShaderProvider test_shaders() {
  return [](const std::string&, const std::string& path, const std::string& bindings) {
    auto it = kShaders.find(path);
    return it == kShaders.end() ? builtin_spirv(path, bindings) : compile_glsl(path, it->second, bindings);
  };
}

// squares (GPU) -> prefix sums of them (CPU, sized when it runs) -> each plus 1000 (GPU).
std::vector<PassDecl> passes() {
  std::vector<PassDecl> p;
  p.push_back(PassDecl("squares", PassType::compute)
                  .write("squares", Use::storage_write, BufferDecl{kinds::buffer, kCount * 4})
                  .shader("test/squares.comp")
                  .run([](PassContext& ctx) {
                    ctx.bind_pipeline();
                    ctx.push({Binding::storage(ctx.slot("squares"), "squares")});
                    vkCmdDispatch(ctx.cmd(), 1, 1, 1);
                  }));
  p.push_back(PassDecl("prefix", PassType::cpu)
                  .read("squares", Use::host)
                  .write("prefix", Use::host, BufferDecl{kinds::buffer})
                  .run([](PassContext& ctx) {
                    const std::span<const uint8_t> in = ctx.host("squares");
                    std::vector<uint32_t> values(in.size() / 4);
                    std::memcpy(values.data(), in.data(), in.size());
                    for (size_t i = 1; i < values.size(); ++i) values[i] += values[i - 1];
                    std::vector<uint8_t>& out = ctx.output("prefix");
                    out.resize(values.size() * 4);
                    std::memcpy(out.data(), values.data(), out.size());
                  }));
  p.push_back(
      PassDecl("offset", PassType::compute)
          .read("prefix", Use::storage_read)
          .write("result", Use::storage_write, BufferDecl{kinds::buffer, kCount * 4})
          .shader("test/offset.comp")
          .run([](PassContext& ctx) {
            ctx.bind_pipeline();
            ctx.push({Binding::storage(ctx.slot("prefix"), "prefix"), Binding::storage(ctx.slot("result"), "result")});
            vkCmdDispatch(ctx.cmd(), 1, 1, 1);
          }));
  return p;
}

class MidFrameReadback : public GpuTest, public ::testing::WithParamInterface<bool> {};

TEST_P(MidFrameReadback, CpuPassReadsWhatTheGpuComputedEarlierInTheFrame) {
  const std::vector<PassDecl> decls = passes();
  GraphSettings settings;
  settings.sinks = {"result"};
  settings.capture = GetParam();
  settings.readback = {"result"};
  CompiledGraph graph = compile_graph(decls, {}, settings);
  const CompiledPass& prefix = graph.passes[1];
  ASSERT_EQ(prefix.decl->name, "prefix");
  EXPECT_EQ(prefix.sync.host_reads, GetParam() ? std::vector<std::string>{} : std::vector<std::string>{"squares"})
      << "a capture has read every version back already";
  EXPECT_EQ(prefix.sync.uploads, std::vector<std::string>{"prefix"});

  ExecutionOptions options;
  options.shaders = test_shaders();
  const Execution run = execute_graph(*gpu_, *cache_, graph, {}, options);
  EXPECT_EQ(run.submits, 2u) << "one submit up to the CPU pass, one after it";
  const VersionData* result = run.final_version("result");
  ASSERT_TRUE(result && result->bytes);
  ASSERT_EQ(result->bytes->size(), kCount * 4);
  uint32_t sum = 0;
  for (uint32_t i = 0; i < kCount; ++i) {
    sum += i * i;
    uint32_t value;
    std::memcpy(&value, result->bytes->data() + 4 * i, 4);
    ASSERT_EQ(value, sum + 1000) << "element " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(CaptureOffAndOn, MidFrameReadback, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "capture" : "no_capture"; });

class MidFrameReadbackTimedAlone : public GpuTest {};

// A GPU pass between the one that computes and the CPU pass that reads: with a capture and each
// pass timed alone, the capture's readback has brought the squares over before the CPU pass
// runs, and the CPU pass must still find them on the host.
TEST_F(MidFrameReadbackTimedAlone, AGpuPassBetweenLeavesTheCpuPassItsInput) {
  std::vector<PassDecl> decls = passes();
  decls.insert(decls.begin() + 1, PassDecl("between", PassType::compute)
                                      .write("between", Use::storage_write, BufferDecl{kinds::buffer, kCount * 4})
                                      .shader("test/squares.comp")
                                      .run([](PassContext& ctx) {
                                        ctx.bind_pipeline();
                                        ctx.push({Binding::storage(ctx.slot("between"), "between")});
                                        vkCmdDispatch(ctx.cmd(), 1, 1, 1);
                                      }));
  GraphSettings settings;
  settings.sinks = {"result", "between"};
  settings.capture = true;
  settings.readback = {"result"};
  CompiledGraph graph = compile_graph(decls, {}, settings);
  ExecutionOptions options;
  options.shaders = test_shaders();
  options.pass_timing = PassTiming::alone;
  const Execution run = execute_graph(*gpu_, *cache_, graph, {}, options);
  const VersionData* result = run.final_version("result");
  ASSERT_TRUE(result && result->bytes);
  uint32_t last;
  std::memcpy(&last, result->bytes->data() + 4 * (kCount - 1), 4);
  EXPECT_EQ(last, (kCount - 1) * kCount * (2 * kCount - 1) / 6 + 1000);
}

class FrameSubmits : public GpuTest {};

TEST_F(FrameSubmits, OnlyTheSunsOccludersSplitTheFrame) {
  // The frame's CPU passes read only the scene, the camera and each other's outputs, except
  // shadow.cull, which reads shadow.distant's occluder layer: two submits per frame (when the
  // frame runs as a whole; timing passes alone submits each by itself).
  Scene scene = build_city(1);
  add_default_lighting(scene);
  RenderSettings settings;
  settings.width = 64;
  settings.height = 36;
  settings.pass_timing = PassTiming::overlapped;
  Renderer renderer(*gpu_, scene, settings);
  EXPECT_EQ(renderer.render_frame(0, false).execution.submits, 2u);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
