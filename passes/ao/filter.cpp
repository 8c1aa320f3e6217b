// ao.filter: a depth-aware bilateral filter over ao.gtao's noisy half-resolution output, ao.raw,
// into ao.filtered (the same format). A neighbour in the (2·radius + 1)² window counts by how far
// it lies off the texel's tangent plane, as a share of the texel's depth (so a slanted street
// filters along itself, where a depth ratio would cut it into bands), times the cosine between
// the two normals to a power; sky and NaN depths count nothing. The seeds filter after the AO
// pass and before its temporal pass ([000] [001]); XeGTAO's denoiser weighs edges the same way.
// Skipped with the rest of the chain by ao.enabled=0, and when nothing was drawn (ao.filtered
// then holds its clear value, unoccluded, as ao.raw does).
#include "passes/ao/chain.h"
#include "passes/ao/filter.glsl.h"
#include "passes/ao/stage.h"
#include "passes/core/context.h"

namespace nightcap {

PassDecl ao_filter_pass() {
  return ao_chain_pass("ao.filter")
      .read("frame.views", Use::uniform_buffer)
      .read("ao.raw", Use::sampled)
      .read("depth.half", Use::sampled)
      .read("normals.half", Use::sampled)
      .write("ao.filtered", Use::storage_write, ao_bent_image())
      .skip_when_cleared({"depth.half", "normals.half"})
      .param_int("radius", 1, 0, kAoFilterMaxRadius,
                 "half-resolution pixels from the texel to its window's edge; 0: ao.raw as it is")
      .param_float("plane_tolerance", 0.02, 0.001, 1.0,
                   "a neighbour weighs nothing once it lies this share of the texel's depth off its tangent plane")
      .param_float("normal_power", 8.0, 1.0, 64.0,
                   "a neighbour's weight is the cosine between the two normals to this power")
      .shader("ao/filter.comp")
      .push_constants<AoFilterConstants>()
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(AoFilterConstants{int32_t(ctx.param_int("radius")),
                                             float(ctx.param_float("plane_tolerance")),
                                             float(ctx.param_float("normal_power"))});
        const ImageExtent half = ctx.desc("ao.filtered").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kAoFilterGroupSide),
                      group_count(half.height, kAoFilterGroupSide), 1);
      });
}

}  // namespace nightcap
