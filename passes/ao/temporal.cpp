// ao.temporal: ao.filtered blended into a history of earlier frames (the seeds' temporal AO pass
// [000] [001]), writing ao.bent, what lighting.composite reads, and ao.history, which the next
// frame reprojects. ao.gtao's noise moves each frame, so a still texel's n-th frame weighs 1/n
// (up to 1/frames) and its visibility becomes the mean of as many independent estimates. The
// history is reprojected with motion.half (gbuffer.motion, selected as depth.half is) and rejected
// texel by texel where depth.half a frame ago disagrees with where the texel's point was then:
// with the depth test, a camera cut (the graph clears both histories) and a disocclusion start
// from the current frame. Where motion.mask marks the footprint the history is rejected (at the
// default masked_frames=1): a moving object's occlusion moves with it.
// Skipped with the rest of the chain by ao.enabled=0, and when nothing was drawn (ao.bent then
// holds its clear value, unoccluded, and the history none).
#include "passes/ao/chain.h"
#include "passes/ao/stage.h"
#include "passes/ao/temporal.glsl.h"
#include "passes/core/context.h"

namespace nightcap {

PassDecl ao_temporal_pass() {
  return ao_chain_pass("ao.temporal")
      .read("frame.views", Use::uniform_buffer)
      .read("ao.filtered", Use::sampled)
      .read_previous("ao.history", Use::sampled)
      .read("depth.half", Use::sampled)
      .read_previous("depth.half", Use::sampled)
      .read("motion.half", Use::sampled)
      .read("motion.mask", Use::sampled)
      .write("ao.bent", Use::storage_write, ao_bent_image())
      .write("ao.history", Use::storage_write, ao_history_image())
      .skip_when_cleared({"depth.half"})
      .param_int("frames", 16, 1, 256,
                 "the most frames the history averages: a still texel's n-th frame weighs 1/n up to 1/frames")
      .param_int("masked_frames", 1, 1, 256,
                 "the same where motion.mask marks the texel's footprint; 1: the history is rejected there")
      .param_float("depth_tolerance", 0.02, 0.001, 1.0,
                   "a history texel is rejected when its depth is off the texel's depth a frame ago by more than "
                   "this share of it (plus the depth's change across one texel)")
      .shader("ao/temporal.comp")
      .push_constants<AoTemporalConstants>()
      .run([](PassContext& ctx) {
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(AoTemporalConstants{float(ctx.param_int("frames")), float(ctx.param_int("masked_frames")),
                                               float(ctx.param_float("depth_tolerance"))});
        const ImageExtent half = ctx.desc("ao.bent").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kAoTemporalGroupSide),
                      group_count(half.height, kAoTemporalGroupSide), 1);
      });
}

}  // namespace nightcap
