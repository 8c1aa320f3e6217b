// The full-screen pattern: one triangle over the output, everything else from the declaration.
#include "passes/core/context.h"

namespace nightcap {

void record_fullscreen(PassContext& ctx, const std::string& fragment, std::span<const uint8_t> constants) {
  GraphicsPipelineDesc desc;
  desc.vertex = "frame/fullscreen.vert";
  desc.fragment = fragment;
  desc.push_constant_bytes = uint32_t(constants.size());
  std::vector<Binding> bindings;
  for (const ResourceUse& input : ctx.declaration().inputs) {
    const uint32_t slot = uint32_t(bindings.size());
    switch (input.use) {
      case Use::uniform_buffer:
        bindings.push_back(Binding::uniform(slot, input.resource));
        break;
      case Use::storage_read:
        bindings.push_back(Binding::storage(slot, input.resource));
        break;
      case Use::sampled:
        bindings.push_back(Binding::texture(slot, input.resource, ctx.nearest_clamp()));
        break;
      case Use::host:
        continue;  // read on the CPU when recording, not by the shader
      default:
        throw GraphError(ctx.pass() + ": a full-screen pass cannot bind '" + input.resource + "' for that use");
    }
    desc.bindings.push_back(bindings.back().type);
  }
  std::vector<std::string> targets;
  for (const ResourceUse& output : ctx.declaration().outputs) {
    if (output.use != Use::color_attachment)
      throw GraphError(ctx.pass() + ": a full-screen pass writes colour attachments only, not '" + output.resource +
                       "'");
    targets.push_back(output.resource);
    desc.color_formats.push_back(ctx.desc(output.resource).format);
  }
  ctx.begin_rendering(targets);
  ctx.bind(desc);
  ctx.push(bindings);
  if (!constants.empty()) ctx.push_constants(constants.data(), uint32_t(constants.size()));
  vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
  ctx.end_rendering();
}

}  // namespace nightcap
