// normals.pack: world normals from the 10-bit G-buffer repacked as 8-bit best-fit normals
// with roughness (R8G8B8A8_UNORM), the form SSR and the later screen-space passes read, using
// the table of normals.bfn_lut. Never skipped (frame.md).

#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl normals_pack_pass() {
  return PassDecl("normals.pack", PassType::graphics)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("normals.bfn_lut", Use::sampled)
      .write("normals.packed", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::packed_normal})
      .shader("frame/fullscreen.vert")
      .shader("normals/pack.frag")
      .run([](PassContext& ctx) {
        GraphicsPipelineDesc desc;
        desc.vertex = "frame/fullscreen.vert";
        desc.fragment = "normals/pack.frag";
        desc.bindings.assign(3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
        desc.color_formats = {VK_FORMAT_R8G8B8A8_UNORM};
        ctx.begin_rendering({"normals.packed"});
        ctx.bind(desc);
        VkSampler nearest = ctx.nearest_clamp();
        ctx.push({Binding::texture(0, "gbuffer.normal", nearest), Binding::texture(1, "gbuffer.material", nearest),
                  Binding::texture(2, "normals.bfn_lut", nearest)});
        vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
