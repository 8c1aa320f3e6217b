// lighting.composite: direct diffuse + specular + emission + a uniform ambient term into the
// lit HDR colour. The indirect terms of frame.md (AO, SSR, probes, GI volume, fog) join here
// as their passes arrive.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl lighting_composite_pass() {
  return PassDecl("lighting.composite", PassType::graphics)
      .read("lighting.diffuse", Use::sampled)
      .read("lighting.specular", Use::sampled)
      .read("gbuffer.albedo", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("gbuffer.emissive", Use::sampled)
      .read("scene.depth", Use::sampled)
      .write("lighting.lit", Use::color_attachment, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, ResourceKind::hdr_colour})
      .param("ambient", 0.02, 0.0, 1e6, "uniform ambient radiance (a stand-in for the indirect light to come)")
      .param("sky", 0.004, 0.0, 1e6, "radiance of the night sky where nothing was drawn")
      .compare("lighting.lit", ComparisonContract::floats(0x1p-24, 0x1p-10,
                                                          "the nearest half to the sum "
                                                          "(tests/unit/lighting_composite_test.cpp): "
                                                          "two devices within one half ULP"))
      .fullscreen("lighting/composite.frag", [](const PassContext& ctx) {
        // A cool night ambient and a deep blue sky.
        const float ambient = float(ctx.param("ambient")), sky = float(ctx.param("sky"));
        struct {
          float ambient[4], sky[4];
        } constants{{ambient * 0.8f, ambient * 0.9f, ambient * 1.2f, 0.0f}, {sky * 0.5f, sky * 0.7f, sky * 1.6f, 0.0f}};
        return constants;
      });
}

}  // namespace nightcap
