#include "passes/core/executor.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <deque>
#include <utility>

#include "passes/core/execution_state.h"
#include "passes/core/frame_memory.h"
#include "passes/core/history.h"
#include "passes/core/resource_commands.h"

namespace nightcap {

const VersionData* Execution::final_version(const std::string& resource) const {
  for (auto it = versions.rbegin(); it != versions.rend(); ++it)
    if (it->resource == resource) return &*it;
  return nullptr;
}

// ---- execution -----------------------------------------------------------------------------

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

Subresources whole(const ResourceDesc& d) { return {0, d.extent.mips, 0, d.extent.layers}; }

bool same_shape(const ResourceDesc& a, const ResourceDesc& b) {
  const ImageExtent &x = a.extent, &y = b.extent;
  return a.is_buffer == b.is_buffer && a.format == b.format && a.buffer_size == b.buffer_size && x.width == y.width &&
         x.height == y.height && x.depth == y.depth && x.mips == y.mips && x.layers == y.layers;
}

struct Staging {
  GpuBuffer buffer;
  int version;
};

using HostBytes = std::shared_ptr<const std::vector<uint8_t>>;

// A submitted part of the frame, and how many staging buffers it fills.
struct InFlight {
  GpuDevice::Submission submission;
  size_t staging_end;
};

struct Cleanup {
  GpuDevice& gpu;
  PassContext::Shared& shared;
  std::vector<Staging> staging;
  VkQueryPool queries = VK_NULL_HANDLE;
  std::deque<InFlight> in_flight;
  ~Cleanup() {
    // Nothing may be destroyed while the queue still uses it (after an exception).
    for (InFlight& part : in_flight) {
      vkWaitForFences(gpu.device(), 1, &part.submission.fence, VK_TRUE, UINT64_MAX);
      vkDestroyFence(gpu.device(), part.submission.fence, nullptr);
    }
    for (auto& [name, r] : shared.resources) {
      for (auto& [key, view] : r.views) vkDestroyImageView(gpu.device(), view, nullptr);
      if (!r.owned) continue;
      gpu.destroy(r.image);
      gpu.destroy(r.buffer);
    }
    for (Staging& s : staging) gpu.destroy(s.buffer);
    if (queries) vkDestroyQueryPool(gpu.device(), queries, nullptr);
  }
};

// What the steps of execute_graph share while one frame runs. Members are destroyed in reverse:
// `cleanup` waits for the GPU and destroys the resources before `memory` returns their blocks.
struct FrameRun {
  FrameRun(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph, const ExecutionOptions& options)
      : gpu(gpu),
        graph(graph),
        options(options),
        shared{gpu, cache, options.shaders, VK_NULL_HANDLE, {}, {}, {}, nullptr},
        memory(gpu),
        cleanup{gpu, shared, {}, VK_NULL_HANDLE, {}} {
    result.passes.resize(graph.passes.size());
  }

  GpuDevice& gpu;
  CompiledGraph& graph;
  const ExecutionOptions& options;
  Execution result;
  PassContext::Shared shared;
  std::map<std::string, int> latest;  // resource -> current version index
  // Resources holding their clear value: a skipped pass's fresh outputs, a CPU pass's empty lists.
  std::set<std::string> cleared;
  std::map<std::string, std::string> host_pooled;  // previous(name) -> name, read by CPU passes
  std::map<std::string, VkImageUsageFlags> usage;  // by the GPU passes
  std::set<std::string> cpu_outputs;
  // previous(name) inputs the history pool supplies (a replay imports them instead).
  std::map<std::string, std::string> pooled;  // previous(name) -> name
  std::map<std::string, HistorySlot*> slots;  // previous(name) -> its slot in the pool
  std::set<std::string> cleared_slots;        // those this frame cleared
  FrameMemory memory;
  Cleanup cleanup;
  std::string frame_name;
  size_t harvested = 0;        // staging buffers copied into their versions
  std::vector<int> held_back;  // versions read back, for on_read_back after the frame (alone)

  int add_version(const std::string& name, const ResourceDesc& desc, HostBytes bytes) {
    result.versions.push_back({name, desc, std::move(bytes)});
    latest[name] = static_cast<int>(result.versions.size()) - 1;
    return latest[name];
  }

  void add_imports(const std::map<std::string, HostBytes>& imports) {
    for (const auto& [name, bytes] : imports) {
      auto it = graph.resources.find(name);
      if (it == graph.resources.end()) continue;
      if (bytes->size() != it->second.raw_bytes())
        throw GraphError("imported '" + name + "' has " + std::to_string(bytes->size()) + " bytes, expected " +
                         std::to_string(it->second.raw_bytes()));
      shared.host[name] = bytes;
      add_version(name, it->second, bytes);
    }
  }

  // previous(name) inputs of CPU passes: the bytes the pool kept from the last frame (a replay
  // imports them instead), empty when there is no valid history.
  void bind_host_history(const std::map<std::string, HostBytes>& imports) {
    for (CompiledPass& pass : graph.passes) {
      if (pass.culled || pass.decl->type != PassType::cpu) continue;
      for (BoundUse& in : pass.inputs) {
        if (!in.history || imports.count(in.resource)) continue;
        const std::string resource = history_source(in.resource);
        if (!options.history)
          throw GraphError(pass.decl->name + ": reads the previous frame's '" + resource +
                           "', but this run keeps no history");
        if (!host_pooled.emplace(in.resource, resource).second) continue;
        HostBytes kept = options.history->find_host(resource);
        if (!kept)
          result.history_reset[resource] = "no earlier frame";
        else if (graph.settings.frame.camera_cut)
          result.history_reset[resource] = "camera cut";
        if (result.history_reset.count(resource)) kept = std::make_shared<const std::vector<uint8_t>>();
        ResourceDesc& desc = graph.resources[in.resource];
        desc.buffer_size = kept->size();
        shared.host[in.resource] = kept;
        add_version(in.resource, desc, kept);
      }
    }
    for (CompiledPass& pass : graph.passes)
      for (BoundUse& in : pass.inputs)
        if (host_pooled.count(in.resource)) in.desc = graph.resources.at(in.resource);
  }

  void collect_gpu_usage() {
    for (const CompiledPass& pass : graph.passes) {
      if (pass.culled) continue;
      if (pass.decl->type == PassType::cpu) {
        for (const BoundUse& u : pass.outputs) cpu_outputs.insert(u.resource);
        continue;
      }
      for (const BoundUse& u : pass.inputs) usage[u.resource] |= usage_for(u.use);
      for (const BoundUse& u : pass.outputs) usage[u.resource] |= usage_for(u.use);
    }
  }

  void find_pooled_history() {
    for (const std::string& name : graph.history) pooled[name] = history_source(name);
    if (!options.history)
      for (const CompiledPass& pass : graph.passes)
        for (const BoundUse& in : pass.inputs)
          if (pooled.count(in.resource))
            throw GraphError(pass.decl->name + ": reads the previous frame's '" + pooled.at(in.resource) +
                             "', but this run keeps no history");
  }

  void allocate_transients() {
    std::map<std::string, PhysicalResource*> transients;
    for (const auto& [name, flags] : usage) {
      // A resource no step of the plan touches (an input of a skipped pass only) needs no memory.
      if (pooled.count(name) || cpu_outputs.count(name) || !graph.lifetimes.count(name)) continue;
      PhysicalResource& r = shared.resources[name];
      r.desc = graph.resources.at(name);
      create_resource(gpu, name, r, flags, false);
      transients[name] = &r;
    }
    memory.place(transients, graph.lifetimes, options.alias_memory);
    result.memory_bytes = memory.bytes();
    result.memory_bytes_without_aliasing = memory.bytes_without_aliasing();
  }

  void bind_history_slots() {
    for (const auto& [name, resource] : pooled) {
      const ResourceDesc& desc = graph.resources.at(name);
      HistorySlot* slot = options.history->find(resource);
      const bool reshaped = slot && !same_shape(slot->resource.desc, desc);
      if (!slot || reshaped || slot->usage != usage[name]) {
        HistorySlot fresh;
        fresh.resource.desc = desc;
        fresh.usage = usage[name];
        create_resource(gpu, name, fresh.resource, fresh.usage, true);
        slot = &options.history->replace(resource, std::move(fresh));
      }
      if (!slot->filled)
        result.history_reset[resource] = reshaped ? "size changed" : "no earlier frame";
      else if (graph.settings.frame.camera_cut)
        result.history_reset[resource] = "camera cut";
      PhysicalResource& r = shared.resources[name] = slot->resource;
      r.owned = false;
      slots[name] = slot;
      const GpuDevice::Placement held = r.desc.is_buffer ? gpu.placement(r.buffer) : gpu.placement(r.image);
      result.memory_bytes += held.size;
      result.memory_bytes_without_aliasing += held.size;
    }
  }

  void create_timestamp_queries() {
    auto query_info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query_info.queryCount = static_cast<uint32_t>(2 * graph.passes.size() + 2);
    vk_check(vkCreateQueryPool(gpu.device(), &query_info, nullptr, &cleanup.queries), "vkCreateQueryPool");
    gpu.name(VK_OBJECT_TYPE_QUERY_POOL, cleanup.queries, "pass timestamps");
    vkResetQueryPool(gpu.device(), cleanup.queries, 0, query_info.queryCount);
  }

  void begin_frame() {
    frame_name = options.name.empty() ? "frame " + std::to_string(graph.settings.frame.frame_index) : options.name;
    shared.cmd = gpu.begin_commands(frame_name);
    result.submits = 1;
  }

  void issue_step(const std::vector<PlannedBarrier>& planned) {
    issue(shared.cmd, shared.resources, planned, memory.waits());
  }

  // Copies the staging buffers up to `end` into their versions (after a wait for the GPU).
  void harvest(size_t end) {
    for (; harvested < end; ++harvested) {
      const Staging& s = cleanup.staging[harvested];
      if (s.version < 0) continue;
      VersionData& v = result.versions[s.version];
      const auto* begin = static_cast<const uint8_t*>(s.buffer.mapped);
      v.bytes = std::make_shared<std::vector<uint8_t>>(begin, begin + v.desc.raw_bytes());
      if (!options.on_read_back) continue;
      if (alone())
        held_back.push_back(s.version);
      else
        options.on_read_back(v);
    }
  }

  bool alone() const { return options.pass_timing == PassTiming::alone; }

  // The versions PassTiming::alone held back from on_read_back, now that the frame has run.
  void hand_over_read_backs() {
    for (int version : held_back) options.on_read_back(result.versions[version]);
  }

  void wait_oldest() {
    InFlight part = cleanup.in_flight.front();
    cleanup.in_flight.pop_front();
    gpu.wait(part.submission);
    harvest(part.staging_end);
  }

  // Submits what is recorded so far; with `wait_all`, waits for it and every earlier part, so
  // that everything read back so far is on the host.
  void submit(bool wait_all) {
    cleanup.in_flight.push_back({gpu.submit(std::exchange(shared.cmd, VK_NULL_HANDLE)), cleanup.staging.size()});
    while (cleanup.in_flight.size() > (wait_all ? 0 : 1)) wait_oldest();
  }

  // Submits the frame so far and records the rest in a command buffer of its own.
  void split_frame_after(const CompiledPass& pass, bool wait_all) {
    submit(wait_all);
    shared.cmd = gpu.begin_commands(frame_name + " after " + pass.decl->name);
    ++result.submits;
  }

  // PassTiming::alone: what came before the pass has run; the pass's own commands then run by
  // themselves, timed by the host from their submit to their fence.
  void run_alone(size_t i) {
    CompiledPass& pass = graph.passes[i];
    submit(true);
    shared.cmd = gpu.begin_commands(frame_name + ": " + pass.decl->name);
    issue_step(pass.sync.before_pass);
    record_commands(i);
    if (options.cold_caches) flush_host_caches();
    const auto start = std::chrono::steady_clock::now();
    const GpuDevice::Submission submission = gpu.submit(std::exchange(shared.cmd, VK_NULL_HANDLE));
    gpu.wait(submission);
    result.passes[i].time_ms = ms_since(start);
    result.passes[i].clock = PassClock::host_alone;
    shared.cmd = gpu.begin_commands(frame_name + " after " + pass.decl->name);
    result.submits += 2;
  }

  void upload(const std::string& name) {
    PhysicalResource& r = shared.resources.at(name);
    auto host = shared.host.find(name);
    if (host == shared.host.end()) throw GraphError("no bytes were given for imported '" + name + "'");
    const std::vector<uint8_t>& bytes = *host->second;
    GpuBuffer staging =
        gpu.create_buffer(std::max<size_t>(bytes.size(), 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, "upload " + name);
    if (!bytes.empty()) std::memcpy(staging.mapped, bytes.data(), bytes.size());
    cleanup.staging.push_back({staging, -1});
    if (r.desc.is_buffer) {
      if (!bytes.empty()) {
        VkBufferCopy copy{0, 0, bytes.size()};
        vkCmdCopyBuffer(shared.cmd, staging.buffer, r.buffer.buffer, 1, &copy);
      }
    } else {
      auto regions = raw_copy_regions(r.desc);
      vkCmdCopyBufferToImage(shared.cmd, staging.buffer, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             static_cast<uint32_t>(regions.size()), regions.data());
    }
  }

  // `what`: the resource and the pass that wrote this version, e.g. "gbuffer.normal from gbuffer.opaque".
  void read_back(PhysicalResource& r, int version, const std::string& what) {
    GpuBuffer staging = gpu.create_buffer(std::max<uint64_t>(r.desc.raw_bytes(), 16), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                          true, "readback " + what);
    cleanup.staging.push_back({staging, version});
    if (r.desc.is_buffer) {
      if (r.desc.buffer_size) {
        VkBufferCopy copy{0, 0, r.desc.buffer_size};
        vkCmdCopyBuffer(shared.cmd, r.buffer.buffer, staging.buffer, 1, &copy);
      }
    } else {
      auto regions = raw_copy_regions(r.desc);
      vkCmdCopyImageToBuffer(shared.cmd, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer,
                             static_cast<uint32_t>(regions.size()), regions.data());
    }
  }

  // A NaN in one texel of what the pass wrote, through a staging buffer as uploads are.
  void inject_nan(const NanInjection& nan) {
    const PhysicalResource& r = shared.resources.at(nan.resource);
    const std::vector<uint8_t> texel = quiet_nan_texel(*format_info(r.desc.format));
    GpuBuffer staging = gpu.create_buffer(std::max<size_t>(texel.size(), 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                                          "NaN for " + nan.resource + " after " + nan.pass);
    std::memcpy(staging.mapped, texel.data(), texel.size());
    cleanup.staging.push_back({staging, -1});
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageOffset = {int32_t(nan.x), int32_t(nan.y), 0};
    region.imageExtent = {1, 1, 1};
    vkCmdCopyBufferToImage(shared.cmd, staging.buffer, r.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  }

  // Uploads of imported data the GPU reads.
  void record_uploads() {
    issue_step(graph.before_uploads);
    for (const std::string& name : graph.uploads) upload(name);
  }

  // A slot with valid history is already where the plan's clear barriers would leave it.
  // A slot that holds the clear value already needs no clear.
  bool starts_cleared(const std::string& name) const {
    const HistorySlot& slot = *slots.at(name);
    return (result.history_reset.count(pooled.at(name)) || slot.at_clear_value) && !slot.holds_clear_value;
  }

  // The previous frame's values, or the declared initial value where there is no valid one.
  void record_history_start() {
    std::vector<PlannedBarrier> reset;
    for (const PlannedBarrier& b : graph.before_history_clears)
      if (starts_cleared(b.resource)) reset.push_back(b);
    issue_step(reset);
    std::map<std::string, int> history_versions;
    for (const auto& [name, resource] : pooled) {
      PhysicalResource& r = shared.resources.at(name);
      if (starts_cleared(name)) {
        clear_to(shared.cmd, r, whole(r.desc), r.desc.clear);
        cleared_slots.insert(name);
      }
      history_versions[name] = add_version(name, r.desc, nullptr);
    }
    issue_step(graph.before_history_readback);
    if (graph.settings.capture)
      for (const auto& [name, version] : history_versions) read_back(shared.resources.at(name), version, name);
  }

  // A resource used in two ways (two mips, storage and index buffer) is one input version.
  void record_input_versions(const CompiledPass& pass, PassExecution& exec) const {
    for (const BoundUse& in : pass.inputs)
      if (std::find(exec.inputs.begin(), exec.inputs.end(), latest.at(in.resource)) == exec.inputs.end())
        exec.inputs.push_back(latest.at(in.resource));
  }

  void run_pass(size_t i) {
    if (graph.passes[i].culled) return;
    shared.current = &result.passes[i];
    if (graph.passes[i].decl->type == PassType::cpu)
      run_cpu_pass(i);
    else
      record_gpu_pass(i);
  }

  // ---- a CPU pass ----

  // A CPU pass between the GPU passes: its inputs on the host, its outputs uploaded for the GPU
  // passes after it.
  void run_cpu_pass(size_t i) {
    CompiledPass& pass = graph.passes[i];
    record_input_versions(pass, result.passes[i]);
    // A version a GPU pass computed has no host bytes until the frame so far has run.
    const bool needs_gpu_results =
        pass.runs && std::any_of(pass.inputs.begin(), pass.inputs.end(),
                                 [&](const BoundUse& in) { return !result.versions[latest.at(in.resource)].bytes; });
    if (needs_gpu_results) bring_gpu_results_to_host(pass);
    if (pass.runs) hand_inputs_to_host(pass);
    execute_on_host(i);
    for (const BoundUse& out : pass.outputs)
      if (!pass.runs || (out.desc.is_buffer && shared.host.at(out.resource)->empty()))
        cleared.insert(out.resource);
      else
        cleared.erase(out.resource);
    upload_cpu_outputs(pass);
  }

  // The frame so far runs now, so this pass can read what it computed.
  void bring_gpu_results_to_host(const CompiledPass& pass) {
    issue_step(pass.sync.before_host_reads);
    for (const std::string& resource : pass.sync.host_reads)
      read_back(shared.resources.at(resource), latest.at(resource), resource + " for " + pass.decl->name);
    split_frame_after(pass, true);
  }

  // What the pass reads on the host: each input's latest version, whether this pass brought it
  // over or an earlier readback did (a capture reads outputs back as soon as their part of the
  // frame has run, so a GPU result a few passes old may already be there).
  void hand_inputs_to_host(const CompiledPass& pass) {
    for (const BoundUse& in : pass.inputs) {
      shared.host[in.resource] = result.versions[latest.at(in.resource)].bytes;
      if (!shared.host[in.resource])
        throw GraphError(pass.decl->name + ": '" + in.resource + "' was not copied to the host for it");
    }
  }

  // Runs a CPU pass whose inputs are on the host; its outputs become host data.
  void execute_on_host(size_t i) {
    CompiledPass& pass = graph.passes[i];
    PassExecution& exec = result.passes[i];
    shared.cpu_outputs.clear();
    if (pass.runs) {
      PassContext ctx(shared, pass);
      auto start = std::chrono::steady_clock::now();
      pass.decl->execute(ctx);
      exec.cpu_ms = ms_since(start);
      exec.time_ms = exec.cpu_ms;
    }
    for (BoundUse& out : pass.outputs) {
      auto bytes = std::make_shared<std::vector<uint8_t>>(std::move(shared.cpu_outputs[out.resource]));
      if (out.desc.is_buffer) {
        out.desc.buffer_size = bytes->size();
      } else if (!pass.runs) {
        bytes->assign(out.desc.raw_bytes(), 0);  // a skipped CPU pass leaves cleared images
      } else if (bytes->size() != out.desc.raw_bytes()) {
        throw GraphError(pass.decl->name + ": wrote " + std::to_string(bytes->size()) + " bytes to '" + out.resource +
                         "', which holds " + std::to_string(out.desc.raw_bytes()));
      }
      graph.resources[out.resource] = out.desc;
      shared.host[out.resource] = bytes;
      exec.outputs.push_back(add_version(out.resource, out.desc, bytes));
      // Later passes saw the declared (size 0) description of a CPU buffer.
      for (size_t later = i + 1; later < graph.passes.size(); ++later)
        for (BoundUse& in : graph.passes[later].inputs)
          if (in.resource == out.resource) in.desc = out.desc;
    }
  }

  // Its outputs that GPU passes use, created now that it has run (a buffer's size is known then).
  void upload_cpu_outputs(const CompiledPass& pass) {
    for (const std::string& name : pass.sync.uploads) {
      PhysicalResource& r = shared.resources[name];
      r.desc = graph.resources.at(name);
      create_resource(gpu, name, r, usage[name], true);
    }
    issue_step(pass.sync.before_uploads);
    for (const std::string& name : pass.sync.uploads) upload(name);
  }

  // ---- a GPU pass ----

  void record_gpu_pass(size_t i) {
    CompiledPass& pass = graph.passes[i];
    PassExecution& exec = result.passes[i];
    const bool planned_to_run = pass.runs;
    skip_for_empty_lists(pass);
    // A skipped pass still leaves defined outputs for the passes after it, and a pass that
    // writes part of a fresh output leaves the rest defined.
    issue_step(pass.sync.before_clears);
    for (const PlannedClear& clear : pass.sync.clears)
      if (!clear.only_if_skipped || !pass.runs)
        clear_to(shared.cmd, shared.resources.at(clear.resource), clear.range, clear.value);
    // A pass skipped for cleared inputs records them too: a replay runs it on them.
    if (pass.runs || pass.inputs_known) record_input_versions(pass, exec);
    if (pass.runs && alone()) {
      run_alone(i);
    } else {
      if (planned_to_run) issue_step(pass.sync.before_pass);
      if (pass.runs) record_commands(i);
    }
    if (planned_to_run) issue_step(pass.sync.before_injections);
    if (pass.runs)
      for (const NanInjection& nan : pass.sync.injections) inject_nan(nan);
    read_back_outputs(i, add_output_versions(pass, exec));
  }

  // A list a CPU pass left empty is known only now: a pass it skips either modifies its
  // outputs alone, so leaving them as they are is all that is left to do, or leaves its fresh
  // outputs cleared for passes that skip too (compile_graph checks); its planned barriers
  // are still issued, and the plan after it holds. A kept pass (a replay) runs whatever its
  // inputs.
  void skip_for_empty_lists(CompiledPass& pass) {
    const auto& keep = graph.settings.keep;
    if (pass.runs && !pass.decl->cleared_skips.empty() &&
        std::find(keep.begin(), keep.end(), pass.decl->name) == keep.end())
      if (const auto* skip = pass.decl->cleared_skip(cleared, pass.params)) {
        pass.runs = false;
        // Cleared outputs are not what it computes: nothing for a replay to check.
        pass.inputs_known = !pass.clears_if_skipped;
        pass.reason = skip->reason();
        if (pass.clears_if_skipped) pass.reason += "; its outputs left cleared: every pass that reads them skips too";
      }
  }

  // The pass's commands, labelled for debuggers, between its two timestamps.
  void record_commands(size_t i) {
    CompiledPass& pass = graph.passes[i];
    gpu.begin_label(shared.cmd, pass.decl->name);
    vkCmdWriteTimestamp2(shared.cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries,
                         static_cast<uint32_t>(2 * i));
    PassContext ctx(shared, pass);
    const auto start = std::chrono::steady_clock::now();
    pass.decl->execute(ctx);
    result.passes[i].record_ms = ms_since(start);
    vkCmdWriteTimestamp2(shared.cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, cleanup.queries,
                         static_cast<uint32_t>(2 * i + 1));
    gpu.end_label(shared.cmd);
    result.passes[i].gpu_ms = 0.0;  // filled from the queries after the submit
  }

  // The versions the pass wrote: resource -> version.
  std::map<std::string, int> add_output_versions(const CompiledPass& pass, PassExecution& exec) {
    std::map<std::string, int> written;
    for (const BoundUse& out : pass.outputs) {
      auto folded = pass.folded.find(out.resource);
      if (!pass.runs && out.modifies && folded == pass.folded.end()) {
        // Skipped or folded for what its inputs hold, it left them as they were: the replay
        // checks that.
        if (pass.inputs_known) exec.outputs.push_back(latest.at(out.resource));
        continue;
      }
      // A skipped pass's output that nothing reads has no memory (plan_synchronisation).
      written[out.resource] = add_version(out.resource, graph.resources.at(out.resource), nullptr);
      exec.outputs.push_back(written[out.resource]);
      if (!pass.runs && folded == pass.folded.end())
        cleared.insert(out.resource);
      else
        cleared.erase(out.resource);
    }
    return written;
  }

  void read_back_outputs(size_t i, const std::map<std::string, int>& written) {
    const CompiledPass& pass = graph.passes[i];
    issue_step(pass.sync.before_readback);
    for (const std::string& resource : pass.sync.readback)
      if (written.count(resource))
        read_back(shared.resources.at(resource), written.at(resource), resource + " from " + pass.decl->name);
    if (options.on_read_back && !alone() && !pass.sync.readback.empty() && i + 1 < graph.passes.size())
      split_frame_after(pass, false);
  }

  // ---- the end of the frame ----

  // This frame's final values are the next frame's history.
  void record_history_copy() {
    issue_step(graph.before_history_copy);
    for (const auto& [name, resource] : pooled)
      if (!graph.history_at_clear_value.count(name))
        copy_whole(shared.cmd, shared.resources.at(resource), shared.resources.at(name));
  }

  // What the pool keeps for the next frame, once this frame has run.
  void keep_history() {
    for (const auto& [name, slot] : slots) {
      slot->filled = true;
      slot->at_clear_value = graph.history_at_clear_value.count(name) > 0;
      slot->holds_clear_value = slot->at_clear_value && (slot->holds_clear_value || cleared_slots.count(name));
    }
    for (const auto& [name, resource] : host_pooled) {
      auto written = shared.host.find(resource);
      options.history->keep_host(resource, written != shared.host.end() && written->second
                                               ? written->second
                                               : std::make_shared<const std::vector<uint8_t>>());
    }
  }

  // Only a pass that ran wrote its two timestamps: asking for the pool's every query would answer
  // VK_NOT_READY for the others, and waiting on them would never end.
  void read_timestamps() {
    for (size_t i = 0; i < graph.passes.size(); ++i) {
      if (!result.passes[i].gpu_ms) continue;
      uint64_t stamps[2] = {};
      vk_check(vkGetQueryPoolResults(gpu.device(), cleanup.queries, static_cast<uint32_t>(2 * i), 2, sizeof stamps,
                                     stamps, sizeof stamps[0], VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
               "vkGetQueryPoolResults");
      result.passes[i].gpu_ms = double(stamps[1] - stamps[0]) * gpu.timestamp_period_ns() / 1e6;
      if (result.passes[i].clock == PassClock::host) {
        result.passes[i].time_ms = *result.passes[i].gpu_ms;
        result.passes[i].clock = PassClock::device;
      }
    }
  }
};

}  // namespace

Execution execute_graph(GpuDevice& gpu, PipelineCache& cache, CompiledGraph& graph,
                        const std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>>& imports,
                        const ExecutionOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  FrameRun run(gpu, cache, graph, options);
  run.add_imports(imports);
  run.bind_host_history(imports);
  // Allocate what the GPU passes touch: transients placed together by FrameMemory, history
  // slots from the pool; a CPU pass's outputs when it has run (a buffer's size is known then).
  run.collect_gpu_usage();
  run.find_pooled_history();
  run.allocate_transients();
  run.bind_history_slots();
  run.create_timestamp_queries();
  run.begin_frame();
  try {
    run.record_uploads();
    run.record_history_start();
    for (size_t i = 0; i < graph.passes.size(); ++i) run.run_pass(i);
    run.record_history_copy();
  } catch (...) {
    if (run.shared.cmd) vkEndCommandBuffer(run.shared.cmd);
    throw;
  }
  run.submit(true);
  run.keep_history();
  run.read_timestamps();
  run.result.wall_ms = ms_since(start);
  run.hand_over_read_backs();
  return std::move(run.result);
}

}  // namespace nightcap
