#include "replay/replay.h"

#include <fstream>
#include <sstream>

#include "compare/metrics.h"
#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/assembly/supersample.h"
#include "passes/core/hash.h"
#include "passes/core/isolated.h"
#include "passes/core/shader.h"

namespace nightcap {
namespace {

ResourceDesc desc_of(const ResourceRecord& r) {
  ResourceDesc d;
  d.is_buffer = r.is_buffer;
  d.kind = r.kind;
  d.format = r.format;
  d.extent = r.extent;
  d.buffer_size = r.buffer_size;
  d.cube = r.cube;
  return d;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError("--shader: cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string extension(const std::string& path) {
  const size_t dot = path.rfind('.');
  return dot == std::string::npos ? "" : path.substr(dot);
}

// A GLSL file compiled in place of the recorded shader of one stage (its extension), with the
// bindings the pass's declaration numbers.
struct ShaderOverride {
  std::string stage;
  std::string path, source;
};

// Runs `decl` on `inputs` with `record`'s SPIR-V (read from `shaders_from`), the NaN it
// recorded, and `params`; what it had to do otherwise goes to `notes`.
IsolatedRun run_recorded(GpuDevice& gpu, PipelineCache& cache, const PassDecl& decl, const Capture& shaders_from,
                         const PassRecord& record, const std::map<std::string, IsolatedInput>& inputs,
                         const ParamValues& params, uint32_t width, uint32_t height,
                         const std::optional<ShaderOverride>& override, std::vector<std::string>& notes) {
  std::map<std::string, std::vector<uint32_t>> recorded_spirv;
  for (const ShaderRecord& s : record.shaders) recorded_spirv[s.path] = shaders_from.load_shader(s);
  auto shaders = [&](const std::string&, const std::string& path,
                     const std::string& bindings) -> std::vector<uint32_t> {
    if (override && extension(path) == override->stage) return compile_glsl(override->path, override->source, bindings);
    auto it = recorded_spirv.find(path);
    if (it != recorded_spirv.end()) return it->second;
    notes.push_back("capture has no SPIR-V for " + path + ": built-in shader used");
    return builtin_spirv(path, bindings);
  };
  std::vector<NanInjection> nan_injections;
  if (const std::optional<InjectedNanRecord>& nan = record.injected_nan) {
    nan_injections.push_back({record.name, nan->resource, nan->x, nan->y});
    notes.push_back("NaN injected at texel (" + std::to_string(nan->x) + ", " + std::to_string(nan->y) + ") of " +
                    nan->resource + " as recorded");
  }
  return run_isolated(gpu, cache, decl, inputs, params, width, height, shaders, nan_injections);
}

// What a run of `record`'s pass made, output by output, against what `capture` recorded for it.
// Each output's bytes go to `produced_by_recorded_hash` where given (a chained replay's inputs).
std::vector<OutputCheck> check_outputs(const Capture& capture, const PassRecord& record, const Execution& execution,
                                       BytesByHash* produced_by_recorded_hash) {
  std::vector<OutputCheck> checks;
  const PassExecution& exec = execution.passes.at(0);
  for (const ResourceRecord& out : record.outputs) {
    OutputCheck& check = checks.emplace_back();
    check.resource = out.resource;
    check.recorded_hash = out.hash;
    const VersionData* produced = nullptr;
    for (int v : exec.outputs)
      if (execution.versions[v].resource == out.resource) produced = &execution.versions[v];
    if (!produced || !produced->bytes) {
      check.verdict = Verdict::different;
      check.metric = "not produced by the replay";
      continue;
    }
    check.replayed_hash = content_hash(*produced->bytes);
    if (produced_by_recorded_hash) (*produced_by_recorded_hash)[out.hash] = produced->bytes;
    if (check.replayed_hash == out.hash) {
      check.metric = "bytes";
      continue;
    }
    const ResourceDesc recorded_desc = desc_of(out);
    if (produced->desc.is_buffer != recorded_desc.is_buffer ||
        produced->desc.raw_bytes() != recorded_desc.raw_bytes()) {
      check.verdict = Verdict::different;
      check.metric = "size differs";
      continue;
    }
    ResourceRecord replayed_record = out;
    replayed_record.buffer_size = produced->desc.buffer_size;
    const std::vector<uint8_t> recorded = capture.load(out);
    const ResourcePair pair(out, recorded, replayed_record, *produced->bytes);
    const ResourceComparison cmp = compare_resource(pair);
    check.amount = cmp.max_abs;
    check.metric = cmp.metric;
    check.first_difference = cmp.first_difference;
    check.contract = check_contract(out.contract, pair, cmp);
    // On the same machine a replay is bitwise, unless the recorded contract says the result
    // depends on execution order; then it is held to that contract.
    const bool order_dependent = out.contract.order_dependent && check.contract->holds;
    check.verdict = order_dependent ? Verdict::within_tolerance : Verdict::different;
  }
  return checks;
}

}  // namespace

std::string verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::identical:
      return "identical";
    case Verdict::within_tolerance:
      return "within tolerance";
    case Verdict::different:
      return "different";
  }
  return "";
}

std::map<std::string, IsolatedInput> recorded_inputs(const Capture& capture, const PassRecord& pass,
                                                     const BytesByHash& substitutes) {
  std::map<std::string, IsolatedInput> inputs;
  for (const ResourceRecord& in : pass.inputs) {
    if (inputs.count(in.resource)) continue;
    auto substitute = substitutes.find(in.hash);
    inputs[in.resource] = {desc_of(in), substitute != substitutes.end()
                                            ? substitute->second
                                            : std::make_shared<const std::vector<uint8_t>>(capture.load(in))};
  }
  return inputs;
}

bool ReplayReport::any_different() const {
  for (const PassReplay& p : passes)
    for (const OutputCheck& o : p.outputs)
      if (o.verdict == Verdict::different) return true;
  return false;
}

ReplayReport replay_capture(GpuDevice& gpu, const Capture& capture, const ReplayOptions& options) {
  const FrameRecord& frame = capture.frame(options.frame);
  const std::vector<PassDecl> passes = all_passes();
  check_overrides(passes, options.params);
  for (const std::string& name : options.passes) {
    bool found = false;
    for (const PassRecord& p : frame.passes) found |= p.name == name;
    if (!found) throw SceneError("--pass " + name + ": frame " + std::to_string(options.frame) + " has no such pass");
  }
  for (const auto& [pass, file] : options.shader_files) {
    const PassDecl* decl = find_pass(passes, pass);
    if (!decl) throw SceneError("--shader " + pass + "=" + file + ": no pass named '" + pass + "'");
    bool stage = false;
    for (const std::string& s : decl->shaders) stage |= extension(s) == extension(file);
    if (!stage)
      throw SceneError("--shader " + pass + "=" + file + ": " + pass + " has no " + extension(file) + " shader");
  }

  ReplayReport report;
  report.frame = options.frame;
  report.device = gpu.name();
  PipelineCache cache(gpu);
  BytesByHash replayed_by_recorded_hash;

  for (const PassRecord& record : frame.passes) {
    const bool wanted = options.passes.empty() ||
                        std::find(options.passes.begin(), options.passes.end(), record.name) != options.passes.end();
    if (!wanted) continue;
    PassReplay result;
    result.name = record.name;
    // A pass skipped for its cleared inputs recorded them: running it on them checks that the
    // outputs the graph cleared are what it computes.
    if (!record.ran && record.inputs.empty()) {
      result.reason = "skipped in the capture: " + record.reason;
      report.passes.push_back(result);
      continue;
    }
    if (!record.ran)
      result.notes.push_back("skipped in the capture (" + record.reason +
                             "): run on its recorded inputs to check that its cleared outputs are what it computes");
    const PassDecl* decl = find_pass(passes, record.name);
    if (record.name == kSupersampledPass) {
      result.reason = "the supersampled reference (render --supersample): averaged from renders, not made from inputs";
      report.passes.push_back(result);
      continue;
    }
    if (!decl) {
      result.reason = "this build has no pass named " + record.name;
      report.passes.push_back(result);
      continue;
    }

    const std::map<std::string, IsolatedInput> inputs =
        recorded_inputs(capture, record, options.chain ? replayed_by_recorded_hash : BytesByHash{});
    // The recorded values, and --set's over them.
    ParamOverrides overrides = overrides_of(*decl, record.params);
    for (const auto& [key, values] : options.params)
      for (const auto& [name, value] : values) overrides[key][name] = value;
    const ParamValues params = resolve_params(*decl, overrides);
    std::optional<ShaderOverride> override;
    if (auto it = options.shader_files.find(record.name); it != options.shader_files.end()) {
      override = ShaderOverride{extension(it->second), it->second, read_text(it->second)};
      result.notes.push_back("shader " + it->second + " replaces the recorded " + override->stage + " shader");
    }
    const IsolatedRun run = run_recorded(gpu, cache, *decl, capture, record, inputs, params, frame.width, frame.height,
                                         override, result.notes);
    const Execution& execution = run.execution;
    result.replayed = true;
    result.gpu_ms = execution.passes.at(0).gpu_ms;
    result.cpu_ms = execution.passes.at(0).cpu_ms;
    result.time_ms = execution.passes.at(0).time_ms;
    result.clock = execution.passes.at(0).clock;
    result.outputs = check_outputs(capture, record, execution, &replayed_by_recorded_hash);
    report.passes.push_back(std::move(result));
  }
  return report;
}

PassReplay replay_across(GpuDevice& gpu, const Capture& a, const Capture& b, uint32_t frame_index,
                         const std::string& pass) {
  const FrameRecord& frame_a = a.frame(frame_index);
  const FrameRecord& frame_b = b.frame(frame_index);
  const PassRecord *record_a = nullptr, *record_b = nullptr;
  for (const PassRecord& p : frame_a.passes)
    if (p.name == pass) record_a = &p;
  for (const PassRecord& p : frame_b.passes)
    if (p.name == pass) record_b = &p;
  PassReplay result;
  result.name = pass;
  const std::vector<PassDecl> passes = all_passes();
  const PassDecl* decl = find_pass(passes, pass);
  if (!record_a || !record_b || !record_a->ran || !record_b->ran)
    result.reason = "not run by both captures";
  else if (!decl)
    result.reason = "this build has no pass named " + pass;
  if (!result.reason.empty()) return result;
  PipelineCache cache(gpu);
  const IsolatedRun run = run_recorded(gpu, cache, *decl, b, *record_b, recorded_inputs(a, *record_a), record_b->params,
                                       frame_a.width, frame_a.height, std::nullopt, result.notes);
  result.replayed = true;
  result.gpu_ms = run.execution.passes.at(0).gpu_ms;
  result.cpu_ms = run.execution.passes.at(0).cpu_ms;
  result.time_ms = run.execution.passes.at(0).time_ms;
  result.clock = run.execution.passes.at(0).clock;
  result.outputs = check_outputs(a, *record_a, run.execution, nullptr);
  return result;
}

}  // namespace nightcap
