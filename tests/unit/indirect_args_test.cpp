// Indirect arguments as a declared use: one compute pass writes a dispatch's group counts (and
// clears a buffer), the next dispatches that many groups (PassContext::dispatch_indirect), each
// marking its cell, and the graph's barrier between them covers the indirect read (the
// validation layer's synchronization validation checks it). Using a buffer for indirect
// arguments without declaring it so is a GraphError.
#include <cstring>

#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kCells = 64;  // 8×8 possible groups

const std::map<std::string, std::string> kShaders = {
    {"test/write_args.comp", R"(#version 460
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Args { uint groups[3]; };
layout(set = 0, binding = 1) buffer Marks { uint marks[]; };
void main() {
  marks[gl_LocalInvocationIndex] = 0u;
  if (gl_LocalInvocationIndex == 0u) {
    groups[0] = 5u;
    groups[1] = 3u;
    groups[2] = 1u;
  }
}
)"},
    {"test/mark_groups.comp", R"(#version 460
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) buffer Marks { uint marks[]; };
void main() { marks[gl_WorkGroupID.y * 8u + gl_WorkGroupID.x] = 1u + gl_NumWorkGroups.x * 10u + gl_NumWorkGroups.y * 100u; }
)"},
};

std::vector<PassDecl> passes(Use args_use) {
  std::vector<PassDecl> p;
  p.push_back(PassDecl("args", PassType::compute)
                  .write("dispatch.args", Use::storage_write, BufferDecl{kinds::buffer, 12})
                  .write("marks", Use::storage_write, BufferDecl{kinds::buffer, kCells * 4})
                  .shader("test/write_args.comp")
                  .run([](PassContext& ctx) {
                    ctx.bind_pipeline();
                    ctx.push({Binding::storage(ctx.slot("dispatch.args"), "dispatch.args"),
                              Binding::storage(ctx.slot("marks"), "marks")});
                    vkCmdDispatch(ctx.cmd(), 1, 1, 1);
                  }));
  p.push_back(PassDecl("marks", PassType::compute)
                  .read("dispatch.args", args_use)
                  .modify("marks", Use::storage_write)
                  .shader("test/mark_groups.comp")
                  .run([](PassContext& ctx) {
                    ctx.bind_pipeline();
                    ctx.push({Binding::storage(ctx.slot("marks"), "marks")});
                    ctx.dispatch_indirect("dispatch.args");
                  }));
  return p;
}

class IndirectArgs : public GpuTest {
 protected:
  static Execution run(const std::vector<PassDecl>& decls) {
    GraphSettings settings;
    settings.sinks = {"marks"};
    settings.readback = {"marks"};
    CompiledGraph graph = compile_graph(decls, {}, settings);
    ExecutionOptions options;
    options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
      return compile_glsl(path, kShaders.at(path), bindings);
    };
    return execute_graph(*gpu_, *cache_, graph, {}, options);
  }
};

TEST_F(IndirectArgs, DispatchTakesItsGroupCountFromAnEarlierPass) {
  const std::vector<PassDecl> decls = passes(Use::indirect_args);
  const CompiledGraph graph = compile_graph(decls, {}, [] {
    GraphSettings s;
    s.sinks = {"marks"};
    return s;
  }());
  bool planned = false;
  for (const PlannedBarrier& b : graph.passes[1].sync.before_pass)
    if (b.resource == "dispatch.args") {
      planned = true;
      EXPECT_EQ(b.plan.before.access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
      EXPECT_EQ(b.plan.after.stages, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT);
      EXPECT_EQ(b.plan.after.access, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    }
  EXPECT_TRUE(planned) << "the indirect read waits for the compute write";

  const Execution run = IndirectArgs::run(decls);
  const VersionData* marks = run.final_version("marks");
  ASSERT_TRUE(marks && marks->bytes);
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x) {
      uint32_t value;
      std::memcpy(&value, marks->bytes->data() + 4 * (y * 8 + x), 4);
      EXPECT_EQ(value, x < 5 && y < 3 ? 351u : 0u) << x << "," << y << ": groups 5x3x1 ran, nothing else";
    }
}

TEST_F(IndirectArgs, AnUndeclaredIndirectReadIsAGraphError) {
  try {
    run(passes(Use::storage_read));
    FAIL() << "no error";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("marks: takes indirect arguments from 'dispatch.args' without declaring"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
