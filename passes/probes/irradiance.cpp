// probes.irradiance: each slot's capture as the diffuse light it gives, 9 spherical-harmonic
// coefficients per colour in sky.irradiance's form (GpuSkyIrradiance: convolved with the clamped
// cosine over π), kProbeSlots of them in slot order. The slots captured this frame project the
// first level of their cube in probes.faces no wider than kSkyIrradianceFace (irradiance.comp)
// into the buffer probes.keep carried over from the previous frame; the other slots keep what
// they held. The GI volume gathers it. Skipped when no probe is captured this frame (probes.views
// empty) and in a scene without probes.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/probes/irradiance.glsl.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "passes/sky/ibl.glsl.h"

namespace nightcap {

PassDecl probes_irradiance_pass() {
  return PassDecl("probes.irradiance", PassType::compute)
      .read("probes.plan", Use::host)
      .read("probes.faces", Use::sampled)
      .sampler("probes.faces", bilinear_clamp_sampler())
      .read("probes.views", Use::host)
      .modify("probes.irradiance", Use::storage_write)
      .compare("probes.irradiance",
               ComparisonContract::floats(1e-6, 1e-4, "a float sum of 6144 texels in a fixed order per invocation"))
      .can_disable("reflection probes disabled by settings", "probes")
      .needs("reflection_probes")
      .skip_when_cleared({"probes.views"})
      .push_constants<ProbeIrradianceConstants>()
      .shader("probes/irradiance.comp")
      .run([](PassContext& ctx) {
        const ProbePlan plan = read_probe_plan(ctx.host("probes.plan"));
        const ImageExtent faces = ctx.desc("probes.faces").extent;
        if (plan.captured > kProbeSlots || faces.layers < plan.captured * 6)
          throw GraphError("probes.irradiance: probes.plan records " + std::to_string(plan.captured) + " captures");
        uint32_t level = 0;
        while (level + 1 < faces.mips && mip_size(faces.width, level) > kSkyIrradianceFace) ++level;
        ctx.bind_pipeline();
        ctx.push_declared();
        for (uint32_t capture = 0; capture < plan.captured; ++capture) {
          const uint32_t slot = plan.capture_slot[capture];
          if (slot >= kProbeSlots)
            throw GraphError("probes.irradiance: probes.plan captures slot " + std::to_string(slot));
          ctx.push_constants(ProbeIrradianceConstants{slot, capture, level});
          vkCmdDispatch(ctx.cmd(), 1, 1, 1);
        }
      });
}

}  // namespace nightcap
