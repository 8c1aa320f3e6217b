// lighting.composite: direct diffuse + specular + emission + a uniform ambient term into the
// lit HDR colour; where nothing was drawn, the sky: sky.view's radiance by the pixel's view
// direction when sky.atmosphere holds a record (it, sky.view and frame.constants are optional
// inputs, read together), the constant `sky` otherwise (no directional light, the sky switched
// off, or a frame without the sky's passes). The indirect terms of
// frame.md join as optional inputs, each read when its pass is in the frame: ao.bent's visibility (alpha, sampled
// bilinearly: AO may be half size) darkens the ambient term. SSR, probes, the GI volume and fog are to join the same
// way, a read_optional and an `#ifdef NC_BINDING_<name>` block in the shader each, with the passes that define their
// formats.
#include "passes/core/context.h"
#include "passes/lighting/composite.glsl.h"
#include "passes/lighting/stage.h"

namespace nightcap {
namespace {

// A cool night ambient and a deep blue sky.
glm::vec4 ambient_radiance(double ambient) {
  const float a = float(ambient);
  return {a * 0.8f, a * 0.9f, a * 1.2f, 0.0f};
}
glm::vec4 sky_radiance(double sky) {
  const float s = float(sky);
  return {s * 0.5f, s * 0.7f, s * 1.6f, 0.0f};
}

}  // namespace

PassDecl lighting_composite_pass() {
  return PassDecl("lighting.composite", PassType::graphics)
      .read("lighting.diffuse", Use::sampled)
      .read("lighting.specular", Use::sampled)
      .read("gbuffer.albedo", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("gbuffer.emissive", Use::sampled)
      .read("scene.depth", Use::sampled)
      .read_optional("frame.constants", Use::uniform_buffer)
      .read_optional("sky.atmosphere", Use::uniform_buffer)
      .read_optional("sky.view", Use::sampled)
      .sampler("sky.view", bilinear_clamp_sampler())
      .read_optional("ao.bent", Use::sampled)
      .as("ao")
      .sampler("ao.bent", bilinear_clamp_sampler())
      .write("lighting.lit", Use::color_attachment, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour})
      .param_float("ambient", 0.02, 0.0, 1e6, "uniform ambient radiance (a stand-in for the indirect light to come)")
      .param_float("sky", 0.004, 0.0, 1e6, "radiance of the night sky where nothing was drawn")
      .compare("lighting.lit", ComparisonContract::floats(0x1p-24, 0x1p-10,
                                                          "the nearest half to the sum "
                                                          "(tests/unit/lighting_composite_test.cpp): "
                                                          "two devices within one half ULP"))
      // Nothing drawn (depth 0 everywhere) and no sky.view (skipped: cleared; sky.atmosphere, which
      // the sky's passes skip with, is then empty too): the constant sky at every pixel, as the
      // shader stores it.
      .fold_when_uniform({"scene.depth", "sky.view"},
                         [](const UniformValues& inputs, const ParamValues& params) -> std::optional<UniformValues> {
                           if (!(inputs.at("scene.depth").depthStencil.depth <= 0.0f)) return std::nullopt;
                           const glm::vec4 sky = sky_radiance(params.at("sky"));
                           VkClearValue lit{};
                           for (int c = 0; c < 3; ++c) lit.color.float32[c] = half_rounded(sky[c]);
                           lit.color.float32[3] = 1.0f;
                           return UniformValues{{"lighting.lit", lit}};
                         })
      .fullscreen("lighting/composite.frag", [](const PassContext& ctx) {
        // The record decides, not whether sky.view ran: a replay sees the record, not the frame.
        const bool has_sky = ctx.reads("sky.atmosphere") && !ctx.host("sky.atmosphere").empty();
        return CompositeConstants{ambient_radiance(ctx.param_float("ambient")), sky_radiance(ctx.param_float("sky")),
                                  glm::uvec4(has_sky ? 1u : 0u, 0u, 0u, 0u)};
      });
}

}  // namespace nightcap
