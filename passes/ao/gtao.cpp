// ao.gtao: ground-truth-based ambient occlusion (Jimenez et al. 2016) at half resolution, from
// depth.half and normals.half: ao.raw (R8G8B8A8_UNORM, half) holds the bent normal in world
// space (rgb, 0.5·b + 0.5) and the cosine-weighted visibility (a), whose cone about b has the
// half-angle asin(√a). Slice angles and step offsets follow interleaved gradient noise of the
// pixel, shifted each frame, so that ao.temporal's history averages them; the position of a half
// texel is its footprint's centre under the frame's jittered projection. A sample's weight falls
// from 1 to 0 over the outer `falloff` share of the radius and scales the arc it hides (where
// Jimenez and XeGTAO lower its horizon: docs/frame.md says why), and the depth buffer is a height
// field of slabs `thickness` deep (at the default, everything behind a visible surface is solid).
// ao.filter and ao.temporal follow it (passes/ao/chain.h). Skipped with ao.enabled=0 (frame.md:
// by settings only) and when nothing was drawn; skipped, ao.raw keeps its clear value, the zero
// vector and visibility 1, which occludes nothing.
#include "passes/ao/chain.h"
#include "passes/ao/gtao.glsl.h"
#include "passes/ao/stage.h"
#include "passes/core/context.h"

namespace nightcap {
PassDecl ao_gtao_pass() {
  return ao_chain_pass("ao.gtao")
      .read("frame.views", Use::uniform_buffer)
      .read("frame.constants", Use::uniform_buffer)
      .read("depth.half", Use::sampled)
      .read("normals.half", Use::sampled)
      .write("ao.raw", Use::storage_write, ao_bent_image())
      // Nothing drawn: every texel is sky, which the pass leaves unoccluded, the clear value.
      .skip_when_cleared({"depth.half", "normals.half"})
      .param_float("radius", 1.5, 0.05, 100.0, "world-space radius of the horizon search, metres")
      .param_float("falloff", 0.6, 0.01, 1.0,
                   "outer share of the radius over which an occluder's weight falls from 1 to 0")
      .param_float("max_pixels", 64.0, 1.0, 1024.0, "the most half-resolution pixels the search reaches")
      // Solid: slabs make the city's error against its triangles larger (docs/frame.md).
      .param_float("thickness", 0.0, 0.0, 1000.0,
                   "metres behind a visible surface that count as solid, the rest being open; 0: all of it "
                   "(plain GTAO's horizon)")
      // The defaults are on the benchmark's front of time against error (docs/benchmark.md).
      .param_int("slices", 2, 1, kGtaoMaxSlices, "directions searched per pixel")
      .param_int("steps", 8, 1, kGtaoMaxSteps, "horizon samples per side of each direction")
      .param_int("noise", 1, 0, 1,
                 "1: slice angles and step offsets vary with the pixel and the frame (interleaved gradient "
                 "noise); 0: the same for every pixel")
      .shader("ao/gtao.comp")
      .push_constants<GtaoConstants>()
      .run([](PassContext& ctx) {
        const double thickness = ctx.param_float("thickness");
        ctx.bind_pipeline({int32_t(thickness > 0.0)});  // the shader's SLABS
        ctx.push_declared();
        ctx.push_constants(GtaoConstants{float(ctx.param_float("radius")), float(ctx.param_float("falloff")),
                                         float(ctx.param_float("max_pixels")), float(ctx.param_int("noise")),
                                         float(thickness), int32_t(ctx.param_int("slices")),
                                         int32_t(ctx.param_int("steps"))});
        const ImageExtent half = ctx.desc("ao.raw").extent;
        vkCmdDispatch(ctx.cmd(), group_count(half.width, kGtaoGroupSide), group_count(half.height, kGtaoGroupSide), 1);
      });
}

}  // namespace nightcap
