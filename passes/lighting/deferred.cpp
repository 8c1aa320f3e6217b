// lighting.deferred: direct light from the sun and every local light at every pixel, split
// into diffuse and specular (RGBA16F). The clustered, tiled compute version of frame.md
// (lighting.tiled) replaces it once lights.cluster exists.
#include "passes/core/context.h"
#include "passes/lighting/deferred.glsl.h"
#include "passes/lighting/shared_params.h"
#include "passes/lighting/stage.h"

namespace nightcap {

namespace {

ComparisonContract lighting_contract() {
  return ComparisonContract::floats(0x1p-23, 0x1p-9,
                                    "each device within 2^-10 relative (2^-24 absolute) of the double-precision "
                                    "BRDF where its float inputs allow (tests/unit/lighting_deferred_test.cpp): "
                                    "two within twice that");
}

}  // namespace

PassDecl lighting_deferred_pass() {
  ImageDecl hdr{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
  return PassDecl("lighting.deferred", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("frame.views", Use::uniform_buffer)
      .read("frame.lights", Use::storage_read)
      .read("gbuffer.albedo", Use::sampled)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("scene.depth", Use::sampled)
      .write("lighting.diffuse", Use::color_attachment, hdr)
      .write("lighting.specular", Use::color_attachment, hdr)
      .param_float("intensity_scale", 1.0, 0.0, 1e6, "multiplies every light's intensity")
      .param(min_roughness_param())
      .param(tube_samples_param())
      .compare("lighting.diffuse", lighting_contract())
      .compare("lighting.specular", lighting_contract())
      .skip_when([](const SkipContext& frame) {
        const bool lit = frame.features.count("sun") || frame.features.count("local_lights");
        return lit ? std::string() : std::string("scene has no lights");
      })
      .skip_when_cleared({"scene.depth"})
      .fullscreen("lighting/deferred.frag", [](const PassContext& ctx) {
        return DeferredConstants{float(ctx.param_float("intensity_scale")), float(ctx.param_float("min_roughness")),
                                 int32_t(ctx.param_int("tube_samples"))};
      });
}

}  // namespace nightcap
