// probes.convert: this frame's captures (probes.faces) converted to the probes' dual-paraboloid
// layout and GGX-prefiltered per mip (convert.comp says how), `samples` a texel at mip 1 and 4×
// as many each mip down (as sky.specular: each mip costs the same), into their slots of probes.array,
// which probes.keep carried over from the previous frame; the other slots keep what they held.
// Skipped when no probe is captured this frame (probes.views empty) and in a scene without probes.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/probes/convert.glsl.h"
#include "passes/probes/paraboloid.glsl.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"

namespace nightcap {

PassDecl probes_convert_pass() {
  return PassDecl("probes.convert", PassType::compute)
      .read("probes.plan", Use::host)
      .read("probes.views", Use::host)
      .read("probes.faces", Use::sampled)
      .sampler("probes.faces", trilinear_clamp_sampler())
      .modify("probes.array", Use::storage_write)
      .level_mips("probes.array", {0})
      .param_int("samples", 64, 1, 255,
                 "GGX samples per texel of mip 1; each later mip 4× as many (mip 5: 256×, within lavapipe's "
                 "65535 loop iterations)")
      .can_disable("reflection probes disabled by settings", "probes")
      .needs("reflection_probes")
      .skip_when_cleared({"probes.views"})
      .push_constants<ProbeConvertConstants>()
      .shader("probes/convert.comp")
      .run([](PassContext& ctx) {
        const ProbePlan plan = read_probe_plan(ctx.host("probes.plan"));
        const ImageExtent size = ctx.desc("probes.array").extent;
        if (plan.captured > kProbeSlots || ctx.desc("probes.faces").extent.layers < plan.captured * 6)
          throw GraphError("probes.convert: probes.plan records " + std::to_string(plan.captured) + " captures");
        ctx.bind_pipeline();
        const uint32_t samples = uint32_t(ctx.param_int("samples"));
        for (uint32_t level = 0; level < size.mips; ++level) {
          ctx.push_declared(level);
          const uint32_t side = mip_size(size.width, level);
          // A mip has a quarter of the texels of the one above: four times the samples cost the same.
          const uint32_t level_samples = level == 0 ? 1u : samples << (2 * (level - 1));
          for (uint32_t capture = 0; capture < plan.captured; ++capture) {
            const uint32_t slot = plan.capture_slot[capture];
            if (slot >= kProbeSlots)
              throw GraphError("probes.convert: probes.plan captures slot " + std::to_string(slot));
            ctx.push_constants(ProbeConvertConstants{level, slot, capture, level_samples});
            vkCmdDispatch(ctx.cmd(), group_count(side, kProbeConvertGroupSide),
                          group_count(side, kProbeConvertGroupSide), 2);
          }
        }
      });
}

}  // namespace nightcap
