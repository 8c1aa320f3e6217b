// gbuffer.opaque: the opaque (and alpha-tested) surfaces into the G-buffer of frame.md, depth
// tested against the prepass and writing the stencil material class.
//
// Deviation from frame.md: an extra target, gbuffer.emissive (B10G11R11_UFLOAT), holds the
// emitted radiance. The seeds keep emission as one 8-bit scalar in RT2.a, which cannot carry
// glTF's emissive colour and texture apart from the base colour; RT2.a still holds the
// emissive intensity (log-encoded) as the seeds describe.
#include "passes/core/context.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/frame_passes.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

PassDecl gbuffer_opaque_pass() {
  auto target = [](VkFormat format, ResourceKind kind) { return ImageDecl{format, kind}; };
  return PassDecl("gbuffer.opaque", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.geometry", Use::storage_read)
      .read("scene.geometry", Use::index_buffer)
      .read("draws.gbuffer.opaque", Use::storage_read)
      .read("scene.materials", Use::storage_read)
      .read_all("scene.texture.", Use::sampled)
      .slots("scene.texture.", MaterialTexture::count)
      .modify("scene.depth", Use::depth_attachment)
      .write("gbuffer.albedo", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, ResourceKind::colour))
      .write("gbuffer.normal", Use::color_attachment, target(VK_FORMAT_A2B10G10R10_UNORM_PACK32, ResourceKind::normal))
      .write("gbuffer.material", Use::color_attachment, target(VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::material))
      .write("gbuffer.motion", Use::color_attachment, target(VK_FORMAT_R16G16_SFLOAT, ResourceKind::motion))
      .write("gbuffer.emissive", Use::color_attachment,
             target(VK_FORMAT_B10G11R11_UFLOAT_PACK32, ResourceKind::hdr_colour))
      .raster(RasterState::per_draw(VK_CULL_MODE_BACK_BIT))
      // GREATER_OR_EQUAL: what the prepass drew passes at its own depth. The stencil takes each
      // draw's material class.
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER_OR_EQUAL, true).writing_stencil())
      .skip_when([](const SkipContext& frame) {
        const bool any = frame.features.count("opaque_geometry") || frame.features.count("mask_geometry");
        return any ? std::string() : std::string("scene has no opaque geometry");
      })
      .shader("gbuffer/opaque.vert")
      .shader("gbuffer/opaque.frag")
      .run([](PassContext& ctx) {
        ctx.begin_rendering();
        ctx.bind_pipeline();
        auto bindings = geometry_bindings(ctx, "draws.gbuffer.opaque");
        bindings.push_back(Binding::storage(ctx.slot("scene.materials"), "scene.materials"));
        ctx.push(bindings);
        draw_scene(ctx, "draws.gbuffer.opaque", [&](uint32_t, const GpuMaterial& m) {
          const int32_t indices[MaterialTexture::count] = {m.textures.x, m.textures.y, m.textures.z, m.textures.w,
                                                           m.textures2.x};
          const uint32_t samplers[MaterialTexture::count] = {m.samplers.x, m.samplers.y, m.samplers.z, m.samplers.w,
                                                             m.samplers2.x};
          std::vector<Binding> textures;
          const uint32_t first = ctx.slot("scene.texture.");
          for (uint32_t slot = 0; slot < MaterialTexture::count; ++slot) {
            const bool used = indices[slot] >= 0;
            const std::string name = texture_resource(uint32_t(used ? indices[slot] : m.textures2.w));
            textures.push_back(Binding::texture(first + slot, name, ctx.sampler(unpack_sampler(samplers[slot]))));
          }
          ctx.push(textures);
        });
        ctx.end_rendering();
      });
}

}  // namespace nightcap
