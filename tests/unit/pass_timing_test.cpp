// How the executor times passes (passes/core/pass_time.h). Timed alone, each GPU pass that runs
// is its own submit, timed by the host's clock; what a capture reads back reaches on_read_back
// only once the frame has run, so no encoding runs beside a timed pass; the results are those
// of the frame run as a whole. Overlapped, a pass's time is the device's timestamps.
#include <cstring>

#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kCount = 4096;

const char* kFill = R"(#version 460
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Out { uint values[]; };
void main() { values[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x * 3u; }
)";
const char* kAdd = R"(#version 460
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) readonly buffer In { uint source[]; };
layout(set = 0, binding = 1) buffer Out { uint values[]; };
void main() { values[gl_GlobalInvocationID.x] = source[gl_GlobalInvocationID.x] + 7u; }
)";

ShaderProvider test_shaders() {
  return [](const std::string&, const std::string& path, const std::string& bindings) {
    return compile_glsl(path, path == "test/fill.comp" ? kFill : kAdd, bindings);
  };
}

// A CPU pass, then fill -> add -> add (GPU); each counts, when recorded, into `recorded`.
std::vector<PassDecl> passes(int& recorded) {
  std::vector<PassDecl> p;
  p.push_back(
      PassDecl("plan", PassType::cpu).write("plan", Use::host, BufferDecl{kinds::buffer}).run([](PassContext& ctx) {
        ctx.output("plan").assign(16, 1);
      }));
  p.push_back(PassDecl("fill", PassType::compute)
                  .write("a", Use::storage_write, BufferDecl{kinds::buffer, kCount * 4})
                  .shader("test/fill.comp")
                  .run([&recorded](PassContext& ctx) {
                    ++recorded;
                    ctx.bind_pipeline();
                    ctx.push({Binding::storage(ctx.slot("a"), "a")});
                    vkCmdDispatch(ctx.cmd(), kCount / 64, 1, 1);
                  }));
  for (const char* step : {"b", "c"}) {
    const std::string source = step == std::string("b") ? "a" : "b";
    p.push_back(PassDecl(std::string("add_") + step, PassType::compute)
                    .read(source, Use::storage_read)
                    .write(step, Use::storage_write, BufferDecl{kinds::buffer, kCount * 4})
                    .shader("test/add.comp")
                    .run([&recorded, source, step](PassContext& ctx) {
                      ++recorded;
                      ctx.bind_pipeline();
                      ctx.push({Binding::storage(ctx.slot(source), source), Binding::storage(ctx.slot(step), step)});
                      vkCmdDispatch(ctx.cmd(), kCount / 64, 1, 1);
                    }));
  }
  return p;
}

struct Timed {
  Execution execution;
  std::vector<int> recorded_at_read_back;  // GPU passes recorded when each version was handed over
};

Timed run_frame(GpuDevice& gpu, PipelineCache& cache, PassTiming timing) {
  int recorded = 0;
  const std::vector<PassDecl> decls = passes(recorded);
  GraphSettings settings;
  settings.sinks = {"plan", "c"};
  settings.capture = true;
  CompiledGraph graph = compile_graph(decls, {}, settings);
  Timed timed;
  ExecutionOptions options;
  options.shaders = test_shaders();
  options.pass_timing = timing;
  options.on_read_back = [&](const VersionData&) { timed.recorded_at_read_back.push_back(recorded); };
  timed.execution = execute_graph(gpu, cache, graph, {}, options);
  return timed;
}

class PassTimingTest : public GpuTest {};

TEST_F(PassTimingTest, AloneTimesEachGpuPassByTheHostAndHandsOverReadBacksAfterTheFrame) {
  const Timed alone = run_frame(*gpu_, *cache_, PassTiming::alone);
  const Execution& e = alone.execution;
  ASSERT_EQ(e.passes.size(), 4u);
  EXPECT_EQ(e.passes[0].clock, PassClock::host);
  EXPECT_EQ(e.passes[0].time_ms, e.passes[0].cpu_ms);
  double sum = e.passes[0].time_ms;
  for (size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(e.passes[i].clock, PassClock::host_alone) << i;
    EXPECT_GT(e.passes[i].time_ms, 0.0) << i;
    EXPECT_TRUE(e.passes[i].gpu_ms) << "the timestamps are kept beside the host's time";
    EXPECT_GT(e.passes[i].record_ms, 0.0) << i;
    sum += e.passes[i].time_ms + e.passes[i].record_ms;
  }
  EXPECT_GE(e.wall_ms, sum) << "the frame's wall clock holds every pass's time";
  // Each GPU pass a submit of its own, and one before it for what came earlier.
  EXPECT_GE(e.submits, 1u + 2u * 3u);
  ASSERT_FALSE(alone.recorded_at_read_back.empty());
  for (int recorded : alone.recorded_at_read_back) EXPECT_EQ(recorded, 3) << "a version handed over mid-frame";
}

TEST_F(PassTimingTest, OverlappedTimesByTheDevicesTimestampsAndEncodesWhileTheFrameRuns) {
  const Timed overlapped = run_frame(*gpu_, *cache_, PassTiming::overlapped);
  const Execution& e = overlapped.execution;
  EXPECT_EQ(e.passes[0].clock, PassClock::host);
  for (size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(e.passes[i].clock, PassClock::device) << i;
    ASSERT_TRUE(e.passes[i].gpu_ms);
    EXPECT_EQ(e.passes[i].time_ms, *e.passes[i].gpu_ms) << i;
  }
  EXPECT_LT(overlapped.recorded_at_read_back.front(), 3)
      << "the first outputs are handed over while later passes record";
}

TEST_F(PassTimingTest, BothTimingsComputeTheSameFrame) {
  const Timed alone = run_frame(*gpu_, *cache_, PassTiming::alone),
              overlapped = run_frame(*gpu_, *cache_, PassTiming::overlapped);
  ASSERT_EQ(alone.execution.versions.size(), overlapped.execution.versions.size());
  for (size_t v = 0; v < alone.execution.versions.size(); ++v) {
    const VersionData &a = alone.execution.versions[v], &b = overlapped.execution.versions[v];
    EXPECT_EQ(a.resource, b.resource);
    ASSERT_TRUE(a.bytes && b.bytes) << a.resource;
    EXPECT_EQ(*a.bytes, *b.bytes) << a.resource;
  }
  const VersionData* c = alone.execution.final_version("c");
  ASSERT_TRUE(c && c->bytes);
  uint32_t last = 0;
  std::memcpy(&last, c->bytes->data() + 4 * (kCount - 1), 4);
  EXPECT_EQ(last, (kCount - 1) * 3 + 14);
}

TEST(PassTimingDefault, AloneOnACpuDeviceOnly) {
  EXPECT_EQ(default_pass_timing(true), PassTiming::alone);
  EXPECT_EQ(default_pass_timing(false), PassTiming::overlapped);
  for (PassTiming t : {PassTiming::alone, PassTiming::overlapped})
    EXPECT_EQ(pass_timing_from_name(pass_timing_name(t)), t);
  for (PassClock c : {PassClock::device, PassClock::host_alone, PassClock::host})
    EXPECT_EQ(pass_clock_from_name(pass_clock_name(c)), c);
  EXPECT_FALSE(pass_clock_from_name("gpu"));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
