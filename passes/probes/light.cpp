// probes.light: the captured faces lit (light.comp says how, and where it differs from the
// frame's own passes), into probes.faces: RGBA16F, an array of kProbeSlots cube maps the size of
// probes.gbuffer's faces with their mip chains (2×2 means), cube k holding the k-th captured
// probe's faces in probes.views' order, the rest cleared. Skipped when no probe is captured this
// frame (probes.views empty) and in a scene without probes.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/lighting/shared_params.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/light.glsl.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "passes/sky/luts.h"

namespace nightcap {

PassDecl probes_light_pass() {
  ImageDecl faces{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
  faces.size.mode = SizeRule::Mode::like;
  faces.size.like = "probes.depth";
  faces.layers = kProbeSlots * 6;
  faces.cube = true;
  faces.mips = 0;
  return PassDecl("probes.light", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("frame.views", Use::uniform_buffer)
      .read("probes.views", Use::storage_read)
      .as("views")
      .read("probes.face_draws", Use::storage_read)
      .read("probes.lights", Use::storage_read)
      .read("probes.gbuffer.albedo", Use::sampled)
      .read("probes.gbuffer.normal", Use::sampled)
      .read("probes.gbuffer.material", Use::sampled)
      .read("probes.gbuffer.emissive", Use::sampled)
      .read("probes.gbuffer.occlusion", Use::sampled)
      .read("probes.depth", Use::sampled)
      .read("shadow.distant_data", Use::uniform_buffer)
      .read("shadow.distant", Use::sampled)
      .read("shadow.topdown_data", Use::uniform_buffer)
      .read("shadow.topdown", Use::sampled)
      .read("sky.atmosphere", Use::host)
      .read("sky.cubemap", Use::sampled)
      .sampler("sky.cubemap", bilinear_clamp_sampler())
      .read("sky.irradiance", Use::storage_read)
      .read("sky.specular", Use::sampled)
      .sampler("sky.specular", trilinear_clamp_sampler())
      .read("lighting.dfg", Use::sampled)
      .sampler("lighting.dfg", bilinear_clamp_sampler())
      .write("probes.faces", Use::storage_write, faces)
      .level_mips("probes.faces", {-1, 0})  // the level above the one written (level 0: unused), and that one
      .param(ambient_param())
      .param(night_sky_param())
      .param(multiple_scattering_param())
      .param(min_roughness_param())
      .param(tube_samples_param())
      .param_int("filter_radius", 1, 0, 3, "the sun's shadow filter takes (2r + 1)² texels of shadow.distant")
      .param_float("depth_bias", 0.5, 0, 16, "texels of light depth a receiver may lie behind the map and stay lit")
      .param_float("max_slope", 11.43, 0, 1000, "largest receiver slope carried to the shadow filter's texels")
      .can_disable("reflection probes disabled by settings", "probes")
      .needs("reflection_probes")
      .skip_when_cleared({"probes.views"})
      .push_constants<ProbeLightConstants>()
      .shader("probes/light.comp")
      .run([](PassContext& ctx) {
        const auto face_records = host_records<GpuProbeFace>(ctx.host("probes.face_draws"));
        const ImageExtent size = ctx.desc("probes.faces").extent;
        if (face_records.size() > size.layers)
          throw GraphError("probes.light: probes.face_draws holds " + std::to_string(face_records.size()) +
                           " faces, over " + std::to_string(size.layers));
        // The record decides, not whether sky.view ran: a replay sees the record, not the frame.
        ProbeLightConstants constants{ambient_radiance(ctx.param_float("ambient")),
                                      sky_radiance(ctx.param_float("sky")),
                                      0u,
                                      ctx.flag("multiple_scattering") ? 1u : 0u,
                                      float(ctx.param_float("min_roughness")),
                                      int32_t(ctx.param_int("tube_samples")),
                                      int32_t(ctx.param_int("filter_radius")),
                                      float(ctx.param_float("depth_bias")),
                                      float(ctx.param_float("max_slope"))};
        // The cubes past this frame's captures hold the clear value, so that what the capture
        // records does not depend on earlier frames.
        const uint32_t written = uint32_t(face_records.size());
        if (written < size.layers)
          ctx.clear_layers("probes.faces", written, size.layers - written, ctx.desc("probes.faces").clear);
        ctx.bind_pipeline({int32_t(has_atmosphere(ctx))});
        // Each level reads the one above: in order.
        for (uint32_t level = 0; level < size.mips; ++level) {
          const uint32_t side = mip_size(size.width, level);
          constants.level = level;
          ctx.push_declared(level);
          ctx.push_constants(constants);
          vkCmdDispatch(ctx.cmd(), group_count(side, kProbeLightGroupSide), group_count(side, kProbeLightGroupSide),
                        uint32_t(face_records.size()));
          if (level + 1 < size.mips) ctx.storage_barrier();
        }
      });
}

}  // namespace nightcap
