// The history pool across frames: a pass that reads its own previous output sees the value the
// previous execution left, its declared clear value on the first frame, after a camera cut and
// after a resize; the capture records that history as an input version equal to the previous
// frame's output; after a frame whose writer skipped it reads the clear value, though the pool
// copies nothing then. A CPU pass reading its own previous output gets the bytes it wrote a frame
// earlier, and nothing on the first frame or after a cut.
#include <cstring>

#include "passes/core/history.h"
#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// Adds 1 to every texel of the previous frame's sum.
constexpr const char* kAccumulate = R"(#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D previous_sum;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D sum;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(sum)))) return;
  imageStore(sum, p, vec4(texelFetch(previous_sum, p, 0).r + 1.0));
}
)";

PassDecl accumulate_pass() {
  ImageDecl sum{VK_FORMAT_R32_SFLOAT, kinds::colour};
  sum.clear.color.float32[0] = 10.0f;  // the initial value of the history
  return PassDecl("accumulate", PassType::compute)
      .read_previous("sum", Use::sampled)
      .write("sum", Use::storage_write, sum)
      .shader("test/accumulate.comp")
      .run([](PassContext& ctx) {
        ComputePipelineDesc desc;
        desc.shader = "test/accumulate.comp";
        desc.bindings = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        ctx.bind(desc);
        ctx.push({Binding::texture(0, previous("sum"), ctx.nearest_clamp()), Binding::image(1, "sum")});
        const ImageExtent e = ctx.desc("sum").extent;
        vkCmdDispatch(ctx.cmd(), (e.width + 7) / 8, (e.height + 7) / 8, 1);
      });
}

class History : public GpuTest {
 protected:
  struct Frame {
    std::vector<float> history, sum;  // what the pass read, and wrote
    std::map<std::string, std::string> reset;
  };

  static Frame run_frame(const std::vector<PassDecl>& passes, HistoryPool* pool, uint32_t width, bool cut) {
    GraphSettings settings;
    settings.width = width;
    settings.height = 3;
    settings.sinks = {"sum"};
    settings.frame.camera_cut = cut;
    settings.capture = true;
    CompiledGraph graph = compile_graph(passes, {}, settings);
    ExecutionOptions options;
    options.history = pool;
    options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
      return compile_glsl(path, kAccumulate, bindings);
    };
    const Execution execution = execute_graph(*gpu_, *cache_, graph, {}, options);
    auto floats = [&](int version) {
      const auto& bytes = *execution.versions.at(version).bytes;
      std::vector<float> values(bytes.size() / 4);
      std::memcpy(values.data(), bytes.data(), bytes.size());
      return values;
    };
    const PassExecution& pass = execution.passes.at(0);
    EXPECT_EQ(execution.versions.at(pass.inputs.at(0)).resource, "sum@previous");
    return {floats(pass.inputs.at(0)), floats(pass.outputs.at(0)), execution.history_reset};
  }
};

TEST_F(History, CarriesAcrossFramesAndRestartsOnCutsAndResizes) {
  const std::vector<PassDecl> passes{accumulate_pass()};
  HistoryPool pool(*gpu_);
  auto all = [](const std::vector<float>& values, float expected) {
    for (float v : values)
      if (v != expected) return false;
    return !values.empty();
  };
  using Resets = std::map<std::string, std::string>;

  Frame f0 = run_frame(passes, &pool, 5, false);
  EXPECT_TRUE(all(f0.history, 10.0f)) << "frame 0 reads the declared initial value";
  EXPECT_TRUE(all(f0.sum, 11.0f));
  EXPECT_EQ(f0.reset, (Resets{{"sum", "no earlier frame"}}));

  Frame f1 = run_frame(passes, &pool, 5, false);
  EXPECT_EQ(f1.history, f0.sum) << "frame 1's history is frame 0's output";
  EXPECT_TRUE(all(f1.sum, 12.0f));
  EXPECT_TRUE(f1.reset.empty());

  Frame f2 = run_frame(passes, &pool, 5, true);
  EXPECT_TRUE(all(f2.history, 10.0f)) << "a camera cut restarts the history";
  EXPECT_EQ(f2.reset, (Resets{{"sum", "camera cut"}}));

  Frame f3 = run_frame(passes, &pool, 9, false);
  EXPECT_EQ(f3.history.size(), 9u * 3);
  EXPECT_TRUE(all(f3.history, 10.0f)) << "a resize restarts the history";
  EXPECT_EQ(f3.reset, (Resets{{"sum", "size changed"}}));

  Frame f4 = run_frame(passes, &pool, 9, false);
  EXPECT_EQ(f4.history, f3.sum);
  EXPECT_TRUE(all(f4.sum, 12.0f));
}

// The pass skipped on odd frames: the frame after one that skipped reads the clear value, though
// the pool copied nothing into its slot (it held 11 from the frame before) and clears a slot once
// for a run of skipped frames.
TEST_F(History, AFrameAfterItsWriterSkippedReadsTheClearValue) {
  const std::vector<PassDecl> passes{
      accumulate_pass().skip_when([](const SkipContext& frame) { return frame.frame_index % 2 ? "odd frame" : ""; })};
  HistoryPool pool(*gpu_);
  auto skipped_frame = [&](uint32_t index) {
    GraphSettings settings;
    settings.width = 5;
    settings.height = 3;
    settings.sinks = {"sum"};
    settings.frame.frame_index = index;
    CompiledGraph graph = compile_graph(passes, {}, settings);
    ASSERT_FALSE(graph.passes.at(0).runs);
    EXPECT_EQ(graph.history_at_clear_value, std::set<std::string>{"sum@previous"});
    ExecutionOptions options;
    options.history = &pool;
    execute_graph(*gpu_, *cache_, graph, {}, options);
    const HistorySlot* slot = pool.find("sum");
    ASSERT_NE(slot, nullptr);
    EXPECT_TRUE(slot->at_clear_value);
  };
  ASSERT_EQ(run_frame(passes, &pool, 5, false).sum, std::vector<float>(5 * 3, 11.0f));  // frame 0
  skipped_frame(1);
  EXPECT_FALSE(pool.find("sum")->holds_clear_value) << "frame 1 copied nothing and cleared nothing";
  skipped_frame(3);
  EXPECT_TRUE(pool.find("sum")->holds_clear_value) << "the next frame cleared the slot";
  skipped_frame(5);
  EXPECT_TRUE(pool.find("sum")->holds_clear_value);
  // run_frame compiles frame 0's settings: an even frame, so the pass runs.
  const Frame after = run_frame(passes, &pool, 5, false);
  EXPECT_EQ(after.history, std::vector<float>(5 * 3, 10.0f)) << "the skipped frame's value: the clear value";
  EXPECT_EQ(after.sum, std::vector<float>(5 * 3, 11.0f));
  EXPECT_TRUE(after.reset.empty()) << "a skipped writer is history, not a reset";
  EXPECT_FALSE(pool.find("sum")->holds_clear_value) << "copied into again";
  skipped_frame(7);
  EXPECT_EQ(run_frame(passes, &pool, 5, false).history, std::vector<float>(5 * 3, 10.0f))
      << "cleared at the start of the frame that reads it, over the 11 copied two frames before";
}

TEST_F(History, AGraphThatReadsHistoryNeedsAPool) {
  try {
    run_frame({accumulate_pass()}, nullptr, 4, false);
    ADD_FAILURE() << "expected a GraphError";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("accumulate: reads the previous frame's 'sum', but this run keeps no history"),
              std::string::npos)
        << e.what();
  }
}

// Moves the previous frame's sum one texel left by a transfer copy (PassContext::copy_layer).
PassDecl shift_left_pass() {
  ImageDecl sum{VK_FORMAT_R32_SFLOAT, kinds::colour};
  sum.clear.color.float32[0] = 10.0f;
  return PassDecl("shift", PassType::compute)
      .read_previous("sum", Use::sampled)
      .write("sum", Use::storage_write, sum)
      .run([](PassContext& ctx) { ctx.copy_layer(previous("sum"), 0, "sum", 0, 1, 0); });
}

TEST_F(History, CopyLayerMovesThePreviousFrameAndClearsWhatItUncovers) {
  HistoryPool pool(*gpu_);
  const Frame f0 = run_frame({accumulate_pass()}, &pool, 5, false);
  ASSERT_EQ(f0.sum, std::vector<float>(5 * 3, 11.0f));
  const Frame f1 = run_frame({shift_left_pass()}, &pool, 5, false);
  std::vector<float> want(5 * 3, 11.0f);
  for (int y = 0; y < 3; ++y) want[y * 5 + 4] = 10.0f;  // no texel to its right: the clear value
  EXPECT_EQ(f1.sum, want);
  const Frame f2 = run_frame({shift_left_pass()}, &pool, 5, false);
  for (int y = 0; y < 3; ++y) want[y * 5 + 3] = 10.0f;
  EXPECT_EQ(f2.sum, want) << "the cleared column moved left with the rest";
}

// A CPU pass that appends one byte to what it wrote the frame before.
PassDecl counting_plan_pass() {
  return PassDecl("plan", PassType::cpu)
      .read_previous("plan.record", Use::host)
      .write("plan.record", Use::host, BufferDecl{kinds::buffer})
      .run([](PassContext& ctx) {
        const std::span<const uint8_t> before = ctx.host(previous("plan.record"));
        std::vector<uint8_t>& now = ctx.output("plan.record");
        now.assign(before.begin(), before.end());
        now.push_back(uint8_t(before.size()));
      });
}

TEST_F(History, ACpuPassReadsWhatItWroteAFrameEarlier) {
  HistoryPool pool(*gpu_);
  const std::vector<PassDecl> passes{counting_plan_pass()};  // the compiled graph points into it
  struct Frame {
    std::vector<uint8_t> history, record;
    std::map<std::string, std::string> reset;
  };
  auto run = [&](bool cut) {
    GraphSettings settings;
    settings.sinks = {"plan.record"};
    settings.frame.camera_cut = cut;
    settings.capture = true;
    CompiledGraph graph = compile_graph(passes, {}, settings);
    ExecutionOptions options;
    options.history = &pool;
    const Execution execution = execute_graph(*gpu_, *cache_, graph, {}, options);
    const PassExecution& pass = execution.passes.at(0);
    const VersionData& input = execution.versions.at(pass.inputs.at(0));
    EXPECT_EQ(input.resource, "plan.record@previous");
    EXPECT_EQ(input.desc.buffer_size, input.bytes->size()) << "described by the bytes kept";
    return Frame{*input.bytes, *execution.versions.at(pass.outputs.at(0)).bytes, execution.history_reset};
  };
  using Bytes = std::vector<uint8_t>;
  using Resets = std::map<std::string, std::string>;
  const Frame f0 = run(false);
  EXPECT_EQ(f0.history, Bytes{});
  EXPECT_EQ(f0.record, Bytes{0});
  EXPECT_EQ(f0.reset, (Resets{{"plan.record", "no earlier frame"}}));
  const Frame f1 = run(false);
  EXPECT_EQ(f1.history, f0.record);
  EXPECT_EQ(f1.record, (Bytes{0, 1}));
  EXPECT_TRUE(f1.reset.empty());
  const Frame f2 = run(true);
  EXPECT_EQ(f2.history, Bytes{}) << "a camera cut forgets it";
  EXPECT_EQ(f2.reset, (Resets{{"plan.record", "camera cut"}}));
  EXPECT_EQ(run(false).history, f2.record);
}

TEST_F(History, OnlyACpuPassReadsACpuPassHistory) {
  const PassDecl reader = PassDecl("reader", PassType::compute)
                              .read_previous("plan.record", Use::storage_read)
                              .write("out", Use::storage_write, ImageDecl{VK_FORMAT_R32_SFLOAT, kinds::colour})
                              .run([](PassContext&) {});
  GraphSettings settings;
  settings.sinks = {"out"};
  try {
    compile_graph({counting_plan_pass(), reader}, {}, settings);
    ADD_FAILURE() << "expected a GraphError";
  } catch (const GraphError& e) {
    EXPECT_NE(
        std::string(e.what()).find("reader: reads the previous frame's 'plan.record', a CPU pass's output, on the GPU"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
