#include "passes/assembly/frame_passes.h"
#include "passes/cull/stage.h"
#include "passes/decals/stage.h"
#include "passes/depth/stage.h"
#include "passes/frame/constants.h"
#include "passes/gbuffer/stage.h"
#include "passes/lighting/stage.h"
#include "passes/lights/stage.h"
#include "passes/motion/stage.h"
#include "passes/normals/stage.h"
#include "passes/post/stage.h"
#include "passes/shadow/stage.h"

namespace nightcap {

std::vector<std::string> frame_sinks() {
  return {"final.ldr",           "normals.packed", "depth.pyramid",  "depth.half",      "stencil.half",
          "motion.mask",         "cull.stats",     "cull.occlusion", "lights.clusters", "lights.cluster_indices",
          "lights.cluster_stats"};
}

void add_scene_passes(std::vector<PassDecl>& passes) {
  passes.push_back(frame_constants_pass());
  passes.push_back(cull_main_pass());
  passes.push_back(shadow_distant_plan_pass());
  passes.push_back(shadow_distant_pass());
  passes.push_back(shadow_cull_pass());
  passes.push_back(shadow_cascades_static_pass());
  passes.push_back(shadow_cascades_pass());
  passes.push_back(shadow_local_plan_pass());
  passes.push_back(shadow_local_static_pass());
  passes.push_back(shadow_local_pass());
  passes.push_back(shadow_local_moments_pass());
  passes.push_back(depth_prepass_pass());
  passes.push_back(gbuffer_opaque_pass());
  passes.push_back(gbuffer_dynamic_pass());
  passes.push_back(decals_normal_copy_pass());
  passes.push_back(decals_mesh_pass());
  passes.push_back(decals_projected_pass());
  passes.push_back(depth_convert_pass());
  passes.push_back(motion_stencil_pass());
  passes.push_back(normals_bfn_lut_pass());
  passes.push_back(normals_pack_pass());
  passes.push_back(depth_pyramid_pass());
  passes.push_back(lights_cluster_pass());
  passes.push_back(shadow_sun_resolve_pass());
}

void add_lighting_passes(std::vector<PassDecl>& passes, FrameLighting lighting) {
  if (lighting == FrameLighting::tiled) {
    passes.push_back(lighting_ltc_table_pass());
    passes.push_back(lighting_tiled_pass());
  } else {
    passes.push_back(lighting_deferred_pass());
  }
  passes.push_back(lighting_composite_pass());
}

void add_post_passes(std::vector<PassDecl>& passes, const std::string& lit) {
  for (uint32_t level = 0; level < kBloomLevels; ++level) passes.push_back(bloom_level_pass(level, lit));
  passes.push_back(exposure_pass(lit));
  passes.push_back(tonemap_pass(lit));
}

std::vector<PassDecl> frame_passes(FrameLighting lighting) {
  std::vector<PassDecl> passes;
  add_scene_passes(passes);
  add_lighting_passes(passes, lighting);
  // The post chain reads the composite's colour; TAA's resolve goes between them (frame.md).
  add_post_passes(passes, "lighting.lit");
  return passes;
}

std::vector<PassDecl> all_passes() {
  std::vector<PassDecl> passes = frame_passes(FrameLighting::tiled);
  passes.push_back(lighting_deferred_pass());
  return passes;
}

}  // namespace nightcap
