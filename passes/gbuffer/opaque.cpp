// gbuffer.opaque: the opaque (and alpha-tested) surfaces into the G-buffer of frame.md, depth
// tested against the prepass and writing the stencil material class.
//
// Deviation from frame.md: an extra target, gbuffer.emissive (B10G11R11_UFLOAT), holds the
// emitted radiance. The seeds keep emission as one 8-bit scalar in RT2.a, which cannot carry
// glTF's emissive colour and texture apart from the base colour; RT2.a still holds the
// emissive intensity (log-encoded) as the seeds describe.
//
// Deviation from frame.md: another, gbuffer.occlusion (R8_UNORM, 1 where nothing was drawn), holds
// glTF's occlusion texture, which the composite applies to indirect light alone (multiplied into
// the albedo it would darken direct light too). No RT of frame.md has a free 8-bit channel.
#include <cmath>

#include "passes/core/context.h"
#include "passes/gbuffer/draw_surfaces.h"
#include "passes/gbuffer/kinds.h"
#include "passes/gbuffer/stage.h"

namespace nightcap {
namespace {

// 0.5n + 0.5 in 10-bit codes.
std::array<double, 3> stored_vector(const TexelValues& t) {
  return {t.raw[0] * 2 - 1, t.raw[1] * 2 - 1, t.raw[2] * 2 - 1};
}

const KindRegistration kNormal({
    .kind = kinds::normal,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_stored_normal(stored_vector(t), out);
          if (t.raw.size() > 3) out["hair"] = t.raw[3] != 0.0;
        },
    .draw = [](const TexelValues& t, const KindFrame&) { return stored_normal_picture(stored_vector(t)); },
    .measure = KindMeasure::unit_vector,
});

const KindRegistration kMaterial({
    .kind = kinds::material,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["metalness"] = t.raw[0];
          out["roughness"] = t.raw[1];
          out["translucency"] = t.raw[2];
          out["emissive_luminance"] = std::exp2(16.0 * t.raw[3]) - 1.0;
        },
});

const KindRegistration kOcclusion({
    .kind = kinds::occlusion,
    .describe = [](const TexelValues& t, const KindFrame&,
                   nlohmann::ordered_json& out) { out["occlusion"] = t.raw[0]; },
});

const KindRegistration kMotion({
    .kind = kinds::motion,
    .describe =
        [](const TexelValues& t, const KindFrame& frame, nlohmann::ordered_json& out) {
          out["motion_uv"] = {t.raw[0], t.raw[1]};
          out["motion_pixels"] = {t.raw[0] * frame.output_width, t.raw[1] * frame.output_height};
        },
    .draw =
        [](const TexelValues& t, const KindFrame& frame) {
          return TexelPicture{TexelPicture::Scale::motion,
                              {t.raw[0] * frame.output_width, t.raw[1] * frame.output_height, 0}};
        },
});

}  // namespace

PassDecl gbuffer_opaque_pass() {
  auto target = [](VkFormat format, ResourceKind kind) { return ImageDecl{format, kind}; };
  ImageDecl unoccluded = target(VK_FORMAT_R8_UNORM, kinds::occlusion);
  unoccluded.clear.color = {{1.0f, 0.0f, 0.0f, 0.0f}};
  return surface_pass("gbuffer.opaque", "draws.gbuffer.opaque")
      .write("gbuffer.albedo", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::colour))
      .write("gbuffer.normal", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal))
      .write("gbuffer.material", Use::color_attachment, target(VK_FORMAT_R8G8B8A8_UNORM, kinds::material))
      .write("gbuffer.motion", Use::color_attachment, target(VK_FORMAT_R16G16_SFLOAT, kinds::motion))
      .write("gbuffer.emissive", Use::color_attachment, target(VK_FORMAT_B10G11R11_UFLOAT_PACK32, kinds::hdr_colour))
      .write("gbuffer.occlusion", Use::color_attachment, unoccluded)
      // GREATER_OR_EQUAL: what the prepass drew passes at its own depth. The stencil takes each
      // draw's material class.
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER_OR_EQUAL, true).writing_stencil())
      .skip_when([](const SkipContext& frame) {
        const bool any = frame.features.count("opaque_geometry") || frame.features.count("mask_geometry");
        return any ? std::string() : std::string("scene has no opaque geometry");
      })
      .shader("gbuffer/opaque.vert")
      .shader("gbuffer/opaque.frag");
}

}  // namespace nightcap
