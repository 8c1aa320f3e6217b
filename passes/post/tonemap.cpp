// tonemap: HDR lit colour → display (R8G8B8A8_SRGB) with an exposure multiplier and a filmic
// curve. Bloom, auto-exposure and the grading LUT of frame.md feed it once they exist.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl tonemap_pass() {
  return PassDecl("tonemap", PassType::graphics)
      .read("lighting.lit", Use::sampled)
      .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_SRGB, ResourceKind::colour})
      .param("exposure", 1.0, 0.0, 1e6, "multiplies the HDR colour before the curve")
      .shader("frame/fullscreen.vert")
      .shader("post/tonemap.frag")
      .run([](PassContext& ctx) {
        GraphicsPipelineDesc desc;
        desc.vertex = "frame/fullscreen.vert";
        desc.fragment = "post/tonemap.frag";
        desc.bindings = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        desc.push_constant_bytes = 4;
        desc.color_formats = {VK_FORMAT_R8G8B8A8_SRGB};
        ctx.begin_rendering({"final.ldr"});
        ctx.bind(desc);
        ctx.push({Binding::texture(0, "lighting.lit", ctx.nearest_clamp())});
        const float exposure = float(ctx.param("exposure"));
        ctx.push_constants(&exposure, sizeof(exposure));
        vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
