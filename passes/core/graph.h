// The render graph's compile step, independent of Vulkan objects so it can be unit-tested:
// orders passes by their resource dependencies, culls what nothing consumes or what the scene
// lacks the features for, resolves sizes, and plans the barrier each use needs.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "passes/core/pass.h"

namespace nightcap {

// A mistake in the declarations, caught before anything runs.
struct GraphError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ImportedResource {
  std::string name;
  ResourceDesc desc;
};

// A quiet NaN written into one texel of a pass's output right after the pass runs, so that later
// passes read it on the GPU as they would a NaN the pass computed: a known origin for the tools
// that trace NaNs (`render --inject-nan`, and the replay of such a capture).
struct NanInjection {
  std::string pass, resource;
  uint32_t x = 0, y = 0;  // a texel of mip 0, layer 0
  bool operator==(const NanInjection&) const = default;
};

struct GraphSettings {
  uint32_t width = 1280, height = 720;
  SkipContext frame;
  std::vector<std::string> sinks = {"final.ldr"};  // resources the frame must produce
  // Passes to run even when nothing consumes them and their skip conditions hold (replay).
  std::vector<std::string> keep;
  ParamOverrides params;  // --set and the like: every pass's values are resolved from them (CompiledPass::params)
  // Copies to the host: every version a pass writes (a capture), and the last version of these.
  bool capture = false;
  std::set<std::string> readback;
  std::vector<NanInjection> nan_injections;
};

struct BoundUse {
  std::string resource;
  Use use = Use::sampled;
  bool modifies = false;
  bool history = false;  // previous(name) of a read_previous: from the history pool, or imported
  ResourceDesc desc;
  int producer = -1;   // index into CompiledGraph::passes of the pass that wrote this version; -1: imported
  Subresources range;  // concrete (no kAll) for the uses of a pass that runs
};

// The synchronisation state a use needs.
struct AccessState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
  bool operator==(const AccessState&) const = default;
};

struct BarrierPlan {
  AccessState before, after;  // before.layout is the old layout
  bool operator==(const BarrierPlan&) const = default;
};

// One barrier the executor issues: these subresources of a resource (a buffer: all of it) go
// from `plan.before` to `plan.after`.
struct PlannedBarrier {
  std::string resource;
  Subresources range;  // concrete
  BarrierPlan plan;
  // The first use of these subresources in the frame (planned even where nothing came before
  // it): a resource placed in memory that others used earlier waits here for their last use.
  bool first_use = false;
};

// Subresources set by a transfer clear: to the resource's declared clear value, or to the value
// a fold gave it (PassDecl::fold_when_uniform).
struct PlannedClear {
  std::string resource;
  Subresources range;  // concrete
  VkClearValue value{};
  // A running pass's fresh output, cleared only if an empty list skips the pass at run time
  // (CompiledPass::clears_if_skipped).
  bool only_if_skipped = false;
};

// What the executor does around one pass, in this order; every barrier is planned here.
struct PassSync {
  // A CPU pass that runs: its inputs that GPU passes computed, copied to the host before it
  // (the executor submits the frame so far and waits for it). In a capture every version is
  // already copied after its writer, so this is empty, but the wait is still needed.
  std::vector<PlannedBarrier> before_host_reads;
  std::vector<std::string> host_reads;
  // A GPU pass:
  std::vector<PlannedBarrier> before_clears;
  // A skipped pass's fresh outputs, and the part of a fresh output its pass does not write. A
  // skipped pass's output that nothing reads (no pass that runs, no readback, no history) is
  // not cleared: it costs no memory and no time.
  std::vector<PlannedClear> clears;
  std::vector<PlannedBarrier> before_pass;  // a running pass's inputs and outputs
  // A running pass's NaN injections (GraphSettings::nan_injections), after its commands and
  // before its outputs are read back, so the capture records what later passes read.
  std::vector<PlannedBarrier> before_injections;
  std::vector<NanInjection> injections;
  std::vector<PlannedBarrier> before_readback;
  std::vector<std::string> readback;  // outputs copied to the host after the pass
  // A CPU pass: its outputs that GPU passes use, copied to the GPU after it runs.
  std::vector<PlannedBarrier> before_uploads;
  std::vector<std::string> uploads;
};

// When a resource is in use, in steps of the barrier plan (each list of barriers it plans is a
// step; a resource's commands follow the barriers of their step), and what its last step did:
// whatever takes over its memory afterwards waits for that.
struct Lifetime {
  int first = -1, last = -1;
  AccessState last_use;  // the stages that touched it last and the writes among them
};

struct CompiledPass {
  const PassDecl* decl = nullptr;
  bool runs = false;
  std::string reason;  // why it does not run
  // Skipped because its inputs' values make its results known (PassDecl::skip_when_cleared,
  // fold_when_uniform): its inputs are recorded, and a replay runs it to check.
  bool inputs_known = false;
  // It writes fresh outputs and may be skipped at run time by a CPU pass's empty list: the plan
  // clears those outputs before it, and the executor issues the clears only if it is skipped
  // (every pass reading them then skips too; compile_graph checks).
  bool clears_if_skipped = false;
  // By fold_when_uniform: the value the part of each output it writes is cleared to (a modified
  // output only where that changes it).
  UniformValues folded;
  // Its inputs that are uniform, with a value known before the frame (PassContext::uniform).
  std::set<std::string> uniform_inputs;
  bool culled = false;  // not needed at all: nothing of it is allocated or executed
  // Every parameter it declares, its default or override, checked: what it runs with and the
  // capture records.
  ParamValues params;
  std::vector<BoundUse> inputs, outputs;
  PassSync sync;  // GPU passes that are not culled
};

struct CompiledGraph {
  GraphSettings settings;  // what it was compiled for: output size, sinks, frame
  // The declarations compiled, where some optional input had no producer: copies without it, which
  // CompiledPass::decl points into (else it points into the list compile_graph was given).
  std::shared_ptr<const std::vector<PassDecl>> connected;
  std::vector<CompiledPass> passes;  // execution order
  std::map<std::string, ResourceDesc> resources;
  std::map<std::string, Lifetime> lifetimes;  // every resource a GPU pass or an upload touches
  // Imports that GPU passes use, copied to the GPU before the first pass.
  std::vector<std::string> uploads;
  std::vector<PlannedBarrier> before_uploads;
  // previous(name) inputs the executor's history pool supplies (a replay imports them instead).
  // After the uploads, a slot without valid history, or left at the clear value by a frame that
  // copied nothing into it, is cleared unless it holds that value (before_history_clears is
  // issued for those slots only: a filled slot is already in that state, the previous frame's
  // last use of it having been the copy step) and, in a capture, each is read back; after the
  // last pass each name's final version is copied into its slot (history_at_clear_value: not
  // those whose writers skipped).
  std::vector<std::string> history;
  // Slots whose resource ends the frame at its clear value (its writers skip): not copied into,
  // the pool clears such a slot when it does not hold that value already (HistorySlot).
  std::set<std::string> history_at_clear_value;
  std::vector<PlannedBarrier> before_history_clears, before_history_readback, before_history_copy;
};

// Throws GraphError for: a read of a resource nobody writes or imports, two fresh writers of
// one resource, a modify with no earlier version, a cycle, an unknown `like` size, a buffer
// written by a GPU pass without a declared size, a history of a resource nobody writes (unless
// previous(name) is imported, as replay does) or of a CPU pass's output, a name with '@', a
// subresource range outside its image (or on a buffer), one pass using a subresource in two
// layouts, a 3D array or a cube that is not square with a multiple of 6 layers; and for a NaN
// injection whose pass is unknown or does not run (or runs on the CPU), whose resource is not a
// float colour image the pass writes, or whose texel is outside the resource; and for parameters
// as check_overrides and resolve_params say (passes/core/params.h). An optional input that no
// pass writes and nothing imports is left out of its pass (CompiledGraph::connected).
CompiledGraph compile_graph(const std::vector<PassDecl>& passes, const std::vector<ImportedResource>& imports,
                            const GraphSettings& settings);

// The barrier plan of a compiled graph (passes/core/barrier_plan.cpp): fills `uploads`,
// `before_uploads`, the history steps, `lifetimes` and every pass's `sync`, tracking each mip
// and layer of every resource from UNDEFINED. `imports` are host data from outside the frame.
// compile_graph calls it; it is pure.
void plan_synchronisation(CompiledGraph& graph, const std::set<std::string>& imports);
AccessState required_state(Use use, PassType type, bool depth_format);
AccessState transfer_state(bool write);
bool writes(const AccessState& state);

// What the graph knows of one resource between passes: its layout, the last write, and the
// reads since that write already made visible.
struct SyncState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  AccessState last_write;
  VkPipelineStageFlags2 read_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 read_access = VK_ACCESS_2_NONE;
};

// The barrier a use needs given what happened before, and the updated state. A write waits for
// the last write and every read since (RAW, WAR, WAW); a read waits for the last write unless
// an earlier barrier already made it visible to this stage; a layout change always waits.
// `discard`: the previous contents are not needed (layout UNDEFINED is allowed).
std::optional<BarrierPlan> plan_barrier(SyncState& state, const AccessState& next, bool discard = false);

uint32_t full_mip_count(uint32_t width, uint32_t height);

}  // namespace nightcap
