// gbuffer.opaque: the opaque (and alpha-tested) surfaces into the G-buffer of frame.md, depth
// tested against the prepass and writing the stencil material class.
//
// Deviation from frame.md: an extra target, gbuffer.emissive (B10G11R11_UFLOAT), holds the
// emitted radiance. The seeds keep emission as one 8-bit scalar in RT2.a, which cannot carry
// glTF's emissive colour and texture apart from the base colour; RT2.a still holds the
// emissive intensity (log-encoded) as the seeds describe.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"
#include "passes/gbuffer/draw_surfaces.h"

namespace nightcap {

PassDecl gbuffer_opaque_pass() {
  auto target = [](VkFormat format, ResourceKind kind) { return ImageDecl{format, kind}; };
  return surface_pass("gbuffer.opaque", "draws.gbuffer.opaque")
      .write("gbuffer.albedo", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, ResourceKind::colour))
      .write("gbuffer.normal", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, ResourceKind::normal))
      .write("gbuffer.material", Use::color_attachment, target(VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::material))
      .write("gbuffer.motion", Use::color_attachment, target(VK_FORMAT_R16G16_SFLOAT, ResourceKind::motion))
      .write("gbuffer.emissive", Use::color_attachment,
             target(VK_FORMAT_B10G11R11_UFLOAT_PACK32, ResourceKind::hdr_colour))
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
