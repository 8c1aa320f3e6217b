// Post passes, time against error: bloom's level chain and exposure's histogram.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/core/executor.h"
#include "passes/core/format.h"
#include "passes/core/graph.h"
#include "passes/core/isolated.h"
#include "passes/core/resource_kind.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/post/exposure.glsl.h"
#include "passes/post/stage.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/bloom_reference.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {

// bloom: the six level passes as one graph on an HDR image of the output size (a night scene's
// range: dim surroundings, neon a few hundred times brighter), time summed over the levels, and
// the largest relative error of a level against the double-precision filter of the level above
// as stored (half a half-ULP is 4.9e-4) and of the chain against the filter applied all the way
// down without rounding (tests/unit/bloom_test.cpp bounds both).
void bench_bloom(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exponent(-10.0f, 9.0f), unit(0.0f, 1.0f);
  auto lit = std::make_shared<std::vector<uint8_t>>(size_t(width) * height * 8);
  ref::RgbImage exact_above{width, height, std::vector<std::array<double, 3>>(size_t(width) * height)};
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const bool neon = unit(rng) < 0.01f;
    uint16_t h[4] = {0, 0, 0, nc::float_to_half(1.0f)};
    for (int c = 0; c < 3; ++c) {
      h[c] = nc::float_to_half(neon ? 400.0f * unit(rng) : std::exp2(exponent(rng)));
      exact_above.texels[i][c] = nc::half_to_float(h[c]);
    }
    std::memcpy(lit->data() + 8 * i, h, 8);
  }
  std::vector<nc::PassDecl> passes;
  for (uint32_t level = 0; level < nc::kBloomLevels; ++level)
    passes.push_back(nc::bloom_level_pass(level, "lighting.lit"));
  nc::ResourceDesc desc;
  desc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
  desc.kind = nc::kinds::hdr_colour;
  desc.extent.width = width;
  desc.extent.height = height;
  nc::GraphSettings settings;
  settings.width = width;
  settings.height = height;
  settings.sinks = {"bloom.chain"};
  settings.readback = {"bloom.chain"};
  nc::ExecutionOptions options;
  options.shaders = nc::builtin_shaders();
  // lavapipe's timestamps around these compute passes come out far below the work they do (the
  // frame's figures show it too), so the wall-clock cost is measured as well: the same graph
  // with every level skipped (the chain only cleared) is the baseline.
  nc::GraphSettings skipped = settings;
  skipped.params["bloom"]["enabled"] = 0;  // the levels share the switch (the group `bloom`)
  std::vector<double> times, with_ms, without_ms;
  nc::Execution execution;
  for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
    nc::CompiledGraph graph = nc::compile_graph(passes, {{"lighting.lit", desc}}, settings);
    double start = now_ms();
    execution = nc::execute_graph(gpu, cache, graph, {{"lighting.lit", lit}}, options);
    if (r > 0) with_ms.push_back(now_ms() - start);
    double ms = 0;
    for (const auto& pass : execution.passes) ms += pass.gpu_ms.value_or(0.0);
    if (r > 0) times.push_back(ms);
    nc::CompiledGraph baseline = nc::compile_graph(passes, {{"lighting.lit", desc}}, skipped);
    start = now_ms();
    nc::execute_graph(gpu, cache, baseline, {{"lighting.lit", lit}}, options);
    if (r > 0) without_ms.push_back(now_ms() - start);
  }
  const double wall_ms = median(with_ms) - median(without_ms);
  const nc::VersionData& chain = *execution.final_version("bloom.chain");
  double level_err = 0, chain_err = 0;
  for (uint32_t level = 0; level < chain.desc.extent.mips; ++level) {
    const ref::RgbImage gpu_level = ref::decode_rgba16f(*chain.bytes, chain.desc.extent, level);
    const ref::RgbImage above =
        level == 0 ? exact_above : ref::decode_rgba16f(*chain.bytes, chain.desc.extent, level - 1);
    const ref::RgbImage exact = ref::bloom_level(above, gpu_level.width, gpu_level.height, 1.5);
    if (level == 0)
      exact_above = exact;
    else
      exact_above = ref::bloom_level(exact_above, gpu_level.width, gpu_level.height, 1.5);
    for (size_t i = 0; i < exact.texels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double g = gpu_level.texels[i][c];
        if (exact.texels[i][c] >= 0x1p-14)
          level_err = std::max(level_err, std::abs(g - exact.texels[i][c]) / exact.texels[i][c]);
        if (exact_above.texels[i][c] >= 0x1p-14)
          chain_err = std::max(chain_err, std::abs(g - exact_above.texels[i][c]) / exact_above.texels[i][c]);
      }
  }
  table() << "\n## bloom (" << width << "x" << height << " lit, " << chain.desc.extent.width << "x"
          << chain.desc.extent.height << " chain, " << chain.desc.extent.mips << " levels, sigma 1.5)\n"
          << "bloom.level0-5  gpu " << std::fixed << std::setprecision(3) << median(times) << " ms (timestamps), "
          << wall_ms << " ms wall-clock over the skipped chain, max rel error per level " << std::scientific
          << std::setprecision(2) << level_err << ", down the chain " << chain_err << "\n";
  figure("bloom.gpu_ms", median(times));
  figure("bloom.wall_ms", wall_ms);
  figure("bloom.max_rel_err", level_err);
  figure("bloom.chain_max_rel_err", chain_err);
}

// exposure: time, and the error of the histogram's mean log2 luminance (bin centres) against the
// exact mean over every pixel, for the default 24-EV range and a twice as wide, coarser one.
void bench_exposure(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> level(-10.0, 10.0);
  std::vector<uint16_t> texels;
  double exact = 0;
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const uint16_t h = nc::float_to_half(float(std::exp2(level(rng))));
    texels.insert(texels.end(), {h, h, h, 0x3c00});
    exact += std::log2(double(nc::half_to_float(h)) * (0.2126 + 0.7152 + 0.0722));
  }
  exact /= double(width) * height;
  std::vector<uint8_t> lit(texels.size() * 2);
  std::memcpy(lit.data(), texels.data(), lit.size());
  nc::GpuFrameConstants constants{};
  constants.timing.y = float(nc::kFrameSeconds);
  const nc::IsolatedInput constants_in = constants_input(constants);
  table() << "\n## exposure (" << width << "x" << height << ", log2 luminance uniform in [-10, 10])\n";
  for (const double range : {24.0, 48.0}) {
    nc::ParamValues params = nc::exposure_pass("lighting.lit").default_params();
    params["log2_min"] = -range / 2;
    params["log2_max"] = range / 2;
    std::vector<double> times;
    nc::IsolatedRun run;
    for (int r = 0; r < 3; ++r) {
      run = nc::run_isolated(
          gpu, cache, nc::exposure_pass("lighting.lit"),
          {{"frame.constants", constants_in},
           {"lighting.lit", image(VK_FORMAT_R16G16B16A16_SFLOAT, nc::kinds::hdr_colour, width, height, lit)},
           {nc::previous("exposure.value"),
            image(VK_FORMAT_R32G32B32A32_SFLOAT, nc::kinds::hdr_colour, 1, 1, std::vector<uint8_t>(16, 0))}},
          params, width, height, nc::builtin_shaders());
      times.push_back(gpu_ms(run));
    }
    float value[4];
    std::memcpy(value, run.outputs.at("exposure.value")->data(), sizeof value);
    const double error = std::abs(value[2] - exact);
    const std::string row = "exposure.range" + std::to_string(int(range));
    table() << row << "   gpu " << std::fixed << std::setprecision(3) << median(times) << " ms, |mean - exact| "
            << std::setprecision(5) << error << " EV (bin width " << range / nc::kExposureBins << " EV)\n";
    figure(row + ".gpu_ms", median(times));
    figure(row + ".err_ev", error);
  }
}

}  // namespace nightcap::bench
