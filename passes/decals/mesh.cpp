// decals.mesh: instances of decal materials (posters, puddles: thin meshes on walls and ground)
// drawn over the G-buffer after gbuffer.dynamic [000]. Depth is tested (GREATER_OR_EQUAL with a
// small bias toward the camera, so a decal coplanar with its surface wins everywhere) and never
// written; the stencil is left as it is.
//
// Blending (base colour alpha × texture alpha = the decal's opacity a):
// - gbuffer.albedo and gbuffer.material: fixed-function a·decal + (1 − a)·surface on the colour
//   channels: albedo rgb, material rgb (metalness, roughness, and translucency toward the
//   decal's 0: the decal's layer covers the surface). The write masks keep RT0's alpha (object
//   flags) and RT2's emissive intensity.
// - gbuffer.normal: the custom blend the seeds describe — the shader reads the surface normal
//   from decals.normal_copy (made by decals.normal_copy: a pass cannot sample the target it
//   draws into) and writes normalize((1 − a)·n_surface + a·n_decal) with alpha 1, so the
//   blender (the same on every target: independentBlend is not enabled) passes it through
//   unchanged; the write mask keeps RT1's alpha (the hair flag). Where two mesh decals overlap, the later
//   one blends with the surface under both, not with the earlier decal: the copy is taken once.
// Fragments with a = 0 are discarded, so transparent parts of a decal leave every target as it
// was (a normal read and written back would be renormalised).
//
// Skipped when the scene has no mesh decal, and when none is visible (cull.main left
// draws.decals.mesh empty; decals.normal_copy skips with it).
#include "passes/core/context.h"
#include "passes/decals/stage.h"
#include "passes/gbuffer/draw_surfaces.h"

namespace nightcap {
PassDecl decals_mesh_pass() {
  RasterState raster = RasterState::per_draw(VK_CULL_MODE_BACK_BIT);
  // Reversed-Z: a positive bias moves the decal toward the camera, so it passes GREATER_OR_EQUAL
  // over the surface it lies on whatever the rounding of either.
  raster.depth_bias = DepthBias{1.0f, 1.0f, 0.0f};
  return surface_pass("decals.mesh", "draws.decals.mesh")
      .read("decals.normal_copy", Use::sampled)
      .modify("gbuffer.albedo", Use::color_attachment)
      .modify("gbuffer.normal", Use::color_attachment)
      .modify("gbuffer.material", Use::color_attachment)
      .blend("gbuffer.albedo", BlendState::over_rgb())
      .blend("gbuffer.normal", BlendState::over_rgb())
      .blend("gbuffer.material", BlendState::over_rgb())
      .raster(raster)
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER_OR_EQUAL, false))
      .needs("mesh_decals")
      .skip_when_cleared({"draws.decals.mesh"})
      .shader("gbuffer/opaque.vert")
      .shader("decals/mesh.frag");
}

}  // namespace nightcap
