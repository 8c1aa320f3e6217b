// The benchmarks main runs, a group per file; each prints its table and records its figures (bench_common.h).
#pragma once

#include <cstdint>
#include <string>

#include "passes/assembly/renderer.h"
#include "passes/core/device.h"
#include "passes/core/pipeline_cache.h"
#include "passes/scene/scene.h"

namespace nightcap::bench {

// frame_bench.cpp: whole frames, pass by pass.
void bench_scene(GpuDevice& gpu, const std::string& key, const std::string& label, Scene scene, uint32_t width,
                 uint32_t height, int repeats, bool capture_figures);
void bench_map(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height, int repeats, bool frames);
// frame_bench.cpp: the sky and image-based light on/off in the map's street frame (sky_ibl_on_off_ratio).
void bench_sky_ibl_cost(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
void bench_empty(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

// sky_bench.cpp: the sky's LUTs, time against error.
void bench_sky(GpuDevice& gpu, PipelineCache& cache);

// pass_time_bench.cpp: recorded pass times against the same passes replayed alone.
void bench_pass_times(GpuDevice& gpu, uint32_t width, uint32_t height, int runs);

// capture_bench.cpp: what capturing costs (bench_scene runs bench_capture_cost for the city).
void bench_capture_cost(Renderer& renderer, const RenderSettings& settings, int repeats);
void bench_extra_frames(GpuDevice& gpu, uint32_t width, uint32_t height);

// tools_bench.cpp: the CLI, wall clock.
void bench_startup(GpuDevice& gpu, uint32_t width, uint32_t height);
void bench_diff(GpuDevice& gpu, uint32_t width, uint32_t height);
void bench_report(GpuDevice& gpu, uint32_t width, uint32_t height);

// geometry_bench.cpp: geometry and screen passes.
void bench_normals(GpuDevice& gpu, PipelineCache& cache, uint32_t count);
void bench_depth(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height);
void bench_vertex_streams(const std::string& key, const std::string& label, const Scene& scene);
void bench_motion_stencil(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height);
void bench_decals(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

// post_bench.cpp: post passes.
void bench_bloom(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height);
void bench_exposure(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height);

// area_light_bench.cpp: tube and sphere lights.
void bench_tube_samples(GpuDevice& gpu, uint32_t width, uint32_t height);
void bench_tube_quality(GpuDevice& gpu, uint32_t width, uint32_t height);
void bench_ltc();

// light_list_bench.cpp: light lists.
void bench_cluster(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height, int repeats);
void bench_tiled(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height, int repeats);
void bench_cluster_shape(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height, int repeats);

// shadow_bench.cpp: the sun's shadows and the shadow caches.
void bench_shadows(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
void bench_tod(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
void bench_distant(GpuDevice& gpu, uint32_t width, uint32_t height);
void bench_shadow_cache(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
void bench_cascade_budget(GpuDevice& gpu, uint32_t width, uint32_t height);

// local_shadow_bench.cpp: spot light shadows.
void bench_local(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

// probe_bench.cpp: the reflection probes' cost (probes_on_off_ratio, probe_update_ms) and their
// time against error (prefilter samples, probes per frame).
void bench_probes(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
void bench_probe_tradeoffs(GpuDevice& gpu, PipelineCache& cache, uint32_t width, uint32_t height);
// topdown_bench.cpp: the top-down map's cost (topdown_on_off_ratio) and its resolution.
void bench_topdown(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);
// gi_bench.cpp: the GI volume's cost (gi_volume_on_off_ratio) and time against error for its
// spherical-harmonic order and its resolution.
void bench_gi(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

// taa_bench.cpp: TAA's cost in the street frame, and time against error for its settings.
void bench_taa(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

// ao_bench.cpp: the AO chain's cost in the street frame, and time against error for its settings.
void bench_ao(GpuDevice& gpu, uint32_t width, uint32_t height, int repeats);

}  // namespace nightcap::bench
