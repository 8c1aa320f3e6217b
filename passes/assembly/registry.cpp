#include "passes/ao/stage.h"
#include "passes/assembly/frame_passes.h"
#include "passes/cull/stage.h"
#include "passes/decals/stage.h"
#include "passes/depth/stage.h"
#include "passes/frame/constants.h"
#include "passes/gbuffer/stage.h"
#include "passes/gi/stage.h"
#include "passes/lighting/stage.h"
#include "passes/lights/stage.h"
#include "passes/motion/stage.h"
#include "passes/normals/stage.h"
#include "passes/post/stage.h"
#include "passes/probes/stage.h"
#include "passes/shadow/stage.h"
#include "passes/sky/stage.h"
#include "passes/taa/stage.h"

namespace nightcap {

std::vector<std::string> frame_sinks() {
  return {
      "final.ldr",   "normals.packed", "depth.pyramid",   "stencil.half",           "motion.half",
      "cull.stats",  "cull.occlusion", "lights.clusters", "lights.cluster_indices", "lights.cluster_stats",
      "probes.plan", "probes.array",
  };
}

namespace {

// Appends `stage_passes`, in order, as part of `stage`.
void add_stage(std::vector<PassDecl>& passes, const char* stage, std::vector<PassDecl> stage_passes) {
  for (PassDecl& pass : stage_passes) {
    pass.stage = stage;
    passes.push_back(std::move(pass));
  }
}

}  // namespace

void add_scene_passes(std::vector<PassDecl>& passes) {
  add_stage(passes, "setup", {frame_constants_pass(), cull_main_pass()});
  add_stage(passes, "shadows",
            {shadow_distant_plan_pass(), shadow_distant_pass(), shadow_cull_pass(), shadow_cascades_static_pass(),
             shadow_cascades_pass(), shadow_local_plan_pass(), shadow_local_static_pass(), shadow_local_pass(),
             shadow_local_moments_pass(), shadow_topdown_plan_pass(), shadow_topdown_pass()});
  add_stage(passes, "probes", {probes_plan_pass(), probes_cull_pass(), probes_gbuffer_pass()});
  add_stage(passes, "geometry",
            {depth_prepass_pass(), gbuffer_opaque_pass(), gbuffer_dynamic_pass(), decals_normal_copy_pass(),
             decals_mesh_pass(), decals_projected_pass(), depth_convert_pass(), motion_stencil_pass(),
             normals_bfn_lut_pass(), normals_pack_pass(), normals_half_pass(), depth_pyramid_pass()});
}

void add_lighting_passes(std::vector<PassDecl>& passes, FrameLighting lighting) {
  // Ambient occlusion at half resolution, from the depth, normal and motion the geometry stage
  // summarised.
  add_stage(passes, "ao", {ao_gtao_pass(), ao_filter_pass(), ao_temporal_pass()});
  // The light lists and the sun's shadow mask are read by lighting alone.
  add_stage(passes, "lighting", {lights_cluster_pass(), shadow_sun_resolve_pass()});
  // The sky's LUTs and cube maps and the DFG table, which the composite's sky and image-based light
  // (and, to come, the probes) read.
  add_stage(passes, "lighting",
            {sky_atmosphere_pass(), sky_transmittance_pass(), sky_multiscattering_pass(), sky_view_pass(),
             sky_aerial_perspective_pass(), sky_cubemap_pass(), sky_irradiance_pass(), sky_specular_pass(),
             lighting_dfg_pass()});
  // The probes' captures are lit as the composite lights the frame, from the sky's tables.
  add_stage(passes, "probes",
            {probes_light_pass(), probes_keep_pass(), probes_convert_pass(), probes_irradiance_pass()});
  // The GI volume gathers the probes' irradiance and the sky's for the composite's indirect diffuse.
  add_stage(passes, "gi", {gi_plan_pass(), gi_volume_pass()});
  if (lighting == FrameLighting::tiled)
    add_stage(passes, "lighting", {lighting_ltc_table_pass(), lighting_tiled_pass()});
  else
    add_stage(passes, "lighting", {lighting_deferred_pass()});
  add_stage(passes, "lighting", {lighting_composite_pass()});
}

void add_post_passes(std::vector<PassDecl>& passes, const std::string& lit) {
  std::vector<PassDecl> post;
  for (uint32_t level = 0; level < kBloomLevels; ++level) post.push_back(bloom_level_pass(level, lit));
  post.push_back(exposure_pass(lit));
  post.push_back(tonemap_pass(lit));
  add_stage(passes, "post", std::move(post));
}

std::vector<PassDecl> frame_passes(FrameLighting lighting) { return frame_passes_resolved_by(taa_pass(), lighting); }

std::vector<PassDecl> frame_passes_resolved_by(PassDecl resolve, FrameLighting lighting) {
  std::vector<PassDecl> passes;
  add_scene_passes(passes);
  add_lighting_passes(passes, lighting);
  // TAA resolves the composite's colour, and post reads the resolved colour (frame.md).
  add_stage(passes, "taa", {std::move(resolve)});
  add_post_passes(passes, "taa.resolved");
  return passes;
}

std::vector<PassDecl> all_passes() {
  std::vector<PassDecl> passes = frame_passes(FrameLighting::tiled);
  add_stage(passes, "lighting", {lighting_deferred_pass()});
  return passes;
}

}  // namespace nightcap
