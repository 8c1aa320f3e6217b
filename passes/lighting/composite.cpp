// lighting.composite: direct diffuse + specular + emission + indirect light into the lit HDR colour
// (lighting.lit), and direct + indirect specular alone into lighting.lit_specular (what SSR and TAA
// are to read). Indirect light: a uniform `ambient` radiance (a floor under the city's bounce
// light) and, when sky.atmosphere holds a record, the sky's image-based light: diffuse from
// sky.irradiance by the normal, specular from sky.specular by the reflection (split sum with
// lighting.dfg, multiple-scattering compensation, horizon occlusion; composite.frag), and every
// surface seen through the air of sky.aerial_perspective (lighting.lit only). Where nothing was
// drawn, the sky: sky.view's radiance by the pixel's view direction with a record, the constant
// `sky` otherwise (no directional light, the sky switched off, or a frame without the sky's
// passes). The sky's resources, frame.constants and frame.views are optional inputs, read together.
// The indirect terms of frame.md join as optional inputs, each read when its pass is in the frame:
// ao.bent's visibility (alpha, sampled bilinearly: AO may be half size) darkens the indirect
// diffuse, as the material's own occlusion (gbuffer.occlusion) does, and its visibility cone about
// the bent normal the indirect specular: by the share of the specular lobe's cone inside it
// (ao/specular_occlusion.glsl), where the material's occlusion gives Lagarde's estimate; the
// reflection probes (probes.slots, probes.array) take the specular's place of the sky's cube map
// inside their boxes: the two nearest a point, each read along its parallax-corrected direction and
// weighted by how deep in its box the point lies (probes/reflection.glsl), the sky making up the
// rest; the sky's diffuse light reaches only where shadow.topdown finds nothing straight above
// (shadow/topdown.glsl); inside the GI volume (gi.volume, gi.volume_data) the indirect diffuse is
// the volume's irradiance instead, trilinear between its cells (gi/volume_lookup.glsl), mixed with
// the sky's over the volume's outer half cell. SSR and fog are to join the same way, a
// read_optional and an `#ifdef NC_BINDING_<name>` block in the shader each, with the passes that
// define their formats.
#include "passes/core/context.h"
#include "passes/lighting/composite.glsl.h"
#include "passes/lighting/shared_params.h"
#include "passes/lighting/stage.h"
#include "passes/probes/capture_layout.h"

namespace nightcap {

PassDecl lighting_composite_pass() {
  return PassDecl("lighting.composite", PassType::graphics)
      .read("lighting.diffuse", Use::sampled)
      .read("lighting.specular", Use::sampled)
      .read("gbuffer.albedo", Use::sampled)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("gbuffer.emissive", Use::sampled)
      .read("gbuffer.occlusion", Use::sampled)
      .read("scene.depth", Use::sampled)
      .read_optional("frame.constants", Use::uniform_buffer)
      .read_optional("frame.views", Use::uniform_buffer)
      .read_optional("sky.atmosphere", Use::uniform_buffer)
      .read_optional("sky.view", Use::sampled)
      .sampler("sky.view", bilinear_clamp_sampler())
      .read_optional("sky.aerial_perspective", Use::sampled)
      .sampler("sky.aerial_perspective", bilinear_clamp_sampler())
      .read_optional("sky.irradiance", Use::storage_read)
      .read_optional("sky.specular", Use::sampled)
      .sampler("sky.specular", trilinear_clamp_sampler())
      .read_optional("lighting.dfg", Use::sampled)
      .sampler("lighting.dfg", bilinear_clamp_sampler())
      .read_optional("probes.slots", Use::storage_read)
      .read_optional("probes.array", Use::sampled)
      .sampler("probes.array", trilinear_clamp_sampler())
      .read_optional("shadow.topdown", Use::sampled)
      .read_optional("shadow.topdown_data", Use::uniform_buffer)
      .read_optional("gi.volume", Use::sampled)
      .read_optional("gi.volume_data", Use::uniform_buffer)
      .read_optional("ao.bent", Use::sampled)
      .as("ao")
      .sampler("ao.bent", bilinear_clamp_sampler())
      .write("lighting.lit", Use::color_attachment, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
      .write("lighting.lit_specular", Use::color_attachment,
             ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
      .param(ambient_param())
      .param(multiple_scattering_param())
      .param(night_sky_param())
      .param(probe_fade_param())
      .compare("lighting.lit", ComparisonContract::floats(0x1p-24, 0x1p-10,
                                                          "the nearest half to the sum "
                                                          "(tests/unit/lighting_composite_test.cpp): "
                                                          "two devices within one half ULP"))
      .compare("lighting.lit_specular",
               ComparisonContract::floats(0x1p-24, 0x1p-10, "the nearest half to the sum, as lighting.lit"))
      // Nothing drawn (depth 0 everywhere) and no sky.view (skipped: cleared; sky.atmosphere, which
      // the sky's passes skip with, is then empty too): the constant sky at every pixel, as the
      // shader stores it, and no specular light.
      .fold_when_uniform({"scene.depth", "sky.view"},
                         [](const UniformValues& inputs, const ParamValues& params) -> std::optional<UniformValues> {
                           if (!(inputs.at("scene.depth").depthStencil.depth <= 0.0f)) return std::nullopt;
                           const glm::vec4 sky = sky_radiance(params.at("sky"));
                           VkClearValue lit{};
                           for (int c = 0; c < 3; ++c) lit.color.float32[c] = half_rounded(sky[c]);
                           lit.color.float32[3] = 1.0f;
                           VkClearValue specular{};
                           specular.color.float32[3] = 1.0f;
                           return UniformValues{{"lighting.lit", lit}, {"lighting.lit_specular", specular}};
                         })
      .fullscreen("lighting/composite.frag", [](const PassContext& ctx) {
        // The record decides, not whether sky.view ran: a replay sees the record, not the frame.
        const bool has_sky = ctx.reads("sky.atmosphere") && !ctx.host("sky.atmosphere").empty();
        const bool has_gi = ctx.reads("gi.volume_data") && !ctx.host("gi.volume_data").empty();
        const size_t probe_slots =
            ctx.reads("probes.slots") ? ctx.host("probes.slots").size() / sizeof(GpuProbeSlot) : 0;
        return CompositeConstants{
            ambient_radiance(ctx.param_float("ambient")), sky_radiance(ctx.param_float("sky")),
            glm::uvec4(has_sky ? 1u : 0u, ctx.flag("multiple_scattering") ? 1u : 0u, has_gi ? 1u : 0u, 0u),
            glm::vec4(float(ctx.param_float("probe_fade_metres")), float(probe_slots), 0.0f, 0.0f)};
      });
}

}  // namespace nightcap
