// Constructors of every pass of the frame; frame_passes() (passes/frame/registry.cpp) lists
// them in frame order.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

// Which pass lights the frame. Both write lighting.diffuse and lighting.specular, so a frame has
// one: lighting.tiled shades each pixel's froxel list of lights.cluster; lighting.deferred every
// light at every pixel, kept as the benchmark's and the tests' baseline.
enum class FrameLighting { tiled, deferred };

// Every pass of the frame, in frame order (the graph sorts them by their dependencies): the
// stages below, and the names of what flows between them. A frame assembled otherwise (a pass
// put between two stages) calls the stages itself.
std::vector<PassDecl> frame_passes(FrameLighting lighting = FrameLighting::tiled);
// Frame constants, culling, shadows, depth, G-buffer, decals, light lists and the sun's shadow.
void add_scene_passes(std::vector<PassDecl>& passes);
// Diffuse and specular light, and lighting.composite's lit colour, lighting.lit.
void add_lighting_passes(std::vector<PassDecl>& passes, FrameLighting lighting);
// Bloom, exposure and tonemap, reading the HDR colour `lit`; tonemap writes final.ldr.
void add_post_passes(std::vector<PassDecl>& passes, const std::string& lit);
// Every pass a frame of either lighting runs: where replay finds a recorded pass's declaration.
std::vector<PassDecl> all_passes();

// What the frame must produce: the displayed image, and the depth-summary and light-list
// resources whose consumers (SSR, AO, TAA) have not landed yet, so they are rendered and
// recorded.
std::vector<std::string> frame_sinks();

PassDecl frame_constants_pass();
PassDecl cull_main_pass();
PassDecl depth_prepass_pass();
PassDecl gbuffer_opaque_pass();
PassDecl gbuffer_dynamic_pass();
PassDecl decals_normal_copy_pass();
PassDecl decals_mesh_pass();
PassDecl decals_projected_pass();
PassDecl depth_convert_pass();
PassDecl motion_stencil_pass();
PassDecl normals_bfn_lut_pass();
PassDecl normals_pack_pass();
PassDecl depth_pyramid_pass();
PassDecl shadow_distant_plan_pass();
PassDecl shadow_distant_pass();
PassDecl shadow_cull_pass();
PassDecl shadow_cascades_pass();
PassDecl shadow_cascades_static_pass();
PassDecl shadow_sun_resolve_pass();
PassDecl shadow_local_plan_pass();
PassDecl shadow_local_static_pass();
PassDecl shadow_local_pass();
PassDecl shadow_local_moments_pass();
PassDecl lights_cluster_pass();
PassDecl lighting_ltc_table_pass();
PassDecl lighting_tiled_pass();
PassDecl lighting_deferred_pass();
PassDecl lighting_composite_pass();
// bloom.chain's levels, one pass each (passes/post/bloom.cpp).
constexpr uint32_t kBloomLevels = 6;
PassDecl bloom_level_pass(uint32_t level, const std::string& lit);
PassDecl exposure_pass(const std::string& lit);
PassDecl tonemap_pass(const std::string& lit);

// depth.linear where nothing was drawn, by default (depth.convert's sky_depth): far beyond any
// surface of a 16 km map, and finite.
constexpr double kSkyDepth = 1e6;

}  // namespace nightcap
