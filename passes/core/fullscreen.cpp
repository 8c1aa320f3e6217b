// The full-screen pattern: one triangle over the output, everything else from the declaration.
#include "passes/core/context.h"

namespace nightcap {

void record_fullscreen(PassContext& ctx, std::span<const uint8_t> constants) {
  std::vector<Binding> bindings;
  for (const ResourceUse& input : ctx.declaration().inputs) {
    switch (input.use) {
      case Use::uniform_buffer:
        bindings.push_back(Binding::uniform(ctx.slot(input.bound_name()), input.bound_name()));
        break;
      case Use::storage_read:
        bindings.push_back(Binding::storage(ctx.slot(input.bound_name()), input.bound_name()));
        break;
      case Use::sampled:
        bindings.push_back(Binding::texture(ctx.slot(input.bound_name()), input.bound_name(), ctx.nearest_clamp()));
        break;
      case Use::host:
        continue;  // read on the CPU when recording, not by the shader
      default:
        throw GraphError(ctx.pass() + ": a full-screen pass cannot bind '" + input.resource + "' for that use");
    }
  }
  for (const ResourceUse& output : ctx.declaration().outputs)
    if (output.use != Use::color_attachment)
      throw GraphError(ctx.pass() + ": a full-screen pass writes colour attachments only, not '" + output.resource +
                       "'");
  ctx.begin_rendering();
  ctx.bind_pipeline();
  ctx.push(bindings);
  if (!constants.empty()) ctx.push_constants(constants.data(), uint32_t(constants.size()));
  vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
  ctx.end_rendering();
}

}  // namespace nightcap
