// depth.convert: device depth → depth.linear (R32_SFLOAT, metres along the view axis), the
// form every later stage samples. The half-resolution depth and stencil of frame.md arrive
// with the geometry stage. Never skipped (frame.md): every later stage reads it.
#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl depth_convert_pass() {
  return PassDecl("depth.convert", PassType::graphics)
      .read("frame.constants", Use::uniform_buffer)
      .read("scene.depth", Use::sampled)
      .write("depth.linear", Use::color_attachment, ImageDecl{VK_FORMAT_R32_SFLOAT, ResourceKind::linear_depth})
      .param("sky_depth", 1e6, 1.0, 3e38, "linear depth written where nothing was drawn (finite, so no Inf)")
      .shader("frame/fullscreen.vert")
      .shader("depth/convert.frag")
      .run([](PassContext& ctx) {
        GraphicsPipelineDesc desc;
        desc.vertex = "frame/fullscreen.vert";
        desc.fragment = "depth/convert.frag";
        desc.bindings = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        desc.push_constant_bytes = 4;
        desc.color_formats = {VK_FORMAT_R32_SFLOAT};
        ctx.begin_rendering({"depth.linear"});
        ctx.bind(desc);
        ctx.push({Binding::uniform(0, "frame.constants"), Binding::texture(1, "scene.depth", ctx.nearest_clamp())});
        const float sky = float(ctx.param("sky_depth"));
        ctx.push_constants(&sky, sizeof(sky));
        vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
