// decals.normal_copy: gbuffer.normal as the geometry passes left it, copied into
// decals.normal_copy for decals.mesh. frame.md has mesh decals read "a copy of RT1" for their
// own blend math [000]: a pass cannot sample the attachment it renders into, so the copy is a
// resource of its own, made by this pass, and the graph places the barriers between them.
//
// gbuffer.normal is declared modified (a storage image this pass reads and leaves as it is, so
// the capture holds an identical version from it): the graph binds a plain read to the frame's
// last version of a resource, which is decals.projected's, after decals.mesh; a modifier reads
// the version before its own, here gbuffer.dynamic's.
//
// Deviation from frame.md: the copy is a pass of its own (frame.md folds it into decals.mesh).
// Skipped, with decals.mesh, when the scene has no mesh decal, and when none is visible
// (draws.decals.mesh, which it reads for that alone, is empty): decals.normal_copy is then left
// cleared, read by no pass that runs. Also skipped when gbuffer.normal is cleared (nothing
// drawn), whose copy is the cleared decals.normal_copy.
#include "passes/core/context.h"
#include "passes/decals/normal_copy.glsl.h"
#include "passes/decals/stage.h"
#include "passes/gbuffer/kinds.h"

namespace nightcap {

PassDecl decals_normal_copy_pass() {
  return PassDecl("decals.normal_copy", PassType::compute)
      .modify("gbuffer.normal", Use::storage_write)
      .write("decals.normal_copy", Use::storage_write, ImageDecl{VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal})
      .read("draws.decals.mesh", Use::host)
      .needs("mesh_decals")
      .skip_when_cleared({"draws.decals.mesh"})
      .skip_when_cleared({"gbuffer.normal"})
      .shader("decals/normal_copy.comp")
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        const ImageExtent size = ctx.desc("decals.normal_copy").extent;
        vkCmdDispatch(ctx.cmd(), group_count(size.width, kNormalCopyGroupSide),
                      group_count(size.height, kNormalCopyGroupSide), 1);
      });
}

}  // namespace nightcap
