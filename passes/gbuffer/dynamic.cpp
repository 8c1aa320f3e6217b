// gbuffer.dynamic: the moving instances into the same G-buffer after gbuffer.opaque [000]. Each
// vertex carries its position at the previous frame's time (GpuDraw::previous_model), so the
// motion target holds the object's own motion over the camera's, and cull.main ORs the moving
// flag (0x02) onto the stencil class it writes.
//
// Skipped when the scene has no moving instance, and when none is visible (cull.main left
// draws.gbuffer.dynamic empty: the executor skips it then, the targets staying as they were).
#include "passes/core/context.h"
#include "passes/gbuffer/draw_surfaces.h"
#include "passes/gbuffer/stage.h"

namespace nightcap {

PassDecl gbuffer_dynamic_pass() {
  return surface_pass("gbuffer.dynamic", "draws.gbuffer.dynamic")
      .modify("gbuffer.albedo", Use::color_attachment)
      .modify("gbuffer.normal", Use::color_attachment)
      .modify("gbuffer.material", Use::color_attachment)
      .modify("gbuffer.motion", Use::color_attachment)
      .modify("gbuffer.emissive", Use::color_attachment)
      .modify("gbuffer.occlusion", Use::color_attachment)
      // No prepass covers moving instances: plain GREATER, and the stencil takes each draw's class.
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER, true).writing_stencil())
      .needs("moving_geometry")
      .skip_when_cleared({"draws.gbuffer.dynamic"})
      .shader("gbuffer/dynamic.vert")
      .shader("gbuffer/dynamic.frag");
}

}  // namespace nightcap
