#include "passes/core/isolated.h"

namespace nightcap {

IsolatedInput buffer_input(std::span<const uint8_t> bytes) {
  IsolatedInput input;
  input.desc.is_buffer = true;
  input.desc.kind = kinds::buffer;
  input.desc.buffer_size = bytes.size();
  input.bytes = std::make_shared<const std::vector<uint8_t>>(bytes.begin(), bytes.end());
  return input;
}

IsolatedRun run_isolated(GpuDevice& gpu, PipelineCache& cache, const PassDecl& pass,
                         const std::map<std::string, IsolatedInput>& inputs, const ParamValues& params, uint32_t width,
                         uint32_t height, const ShaderProvider& shaders,
                         const std::vector<NanInjection>& nan_injections) {
  IsolatedRun run;
  std::vector<ImportedResource> imports;
  std::map<std::string, std::shared_ptr<const std::vector<uint8_t>>> bytes;
  for (const auto& [name, input] : inputs) {
    imports.push_back({name, input.desc});
    bytes[name] = input.bytes;
  }
  GraphSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {};
  settings.keep = {pass.name};
  settings.params = overrides_of(pass, params);
  settings.capture = true;
  settings.nan_injections = nan_injections;
  run.declaration = std::make_shared<const std::vector<PassDecl>>(std::vector<PassDecl>{pass});
  run.graph = compile_graph(*run.declaration, imports, settings);
  ExecutionOptions options;
  options.shaders = shaders;
  options.name = "isolated " + pass.name;
  options.pass_timing = default_pass_timing(gpu.is_cpu());
  // A frame's pass reads inputs that later passes have pushed out of a CPU device's caches;
  // this run has just uploaded them.
  options.cold_caches = gpu.is_cpu();
  run.execution = execute_graph(gpu, cache, run.graph, bytes, options);
  for (int v : run.execution.passes.at(0).outputs) {
    const VersionData& version = run.execution.versions[v];
    run.outputs[version.resource] = version.bytes;
    run.output_descs[version.resource] = version.desc;
  }
  return run;
}

}  // namespace nightcap
