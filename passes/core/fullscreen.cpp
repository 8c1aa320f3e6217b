// The full-screen pattern: one triangle over the output, everything else from the declaration.
#include "passes/core/context.h"

namespace nightcap {

void record_fullscreen(PassContext& ctx, std::span<const uint8_t> constants,
                       const std::vector<int32_t>& specialization) {
  // The targets are drawn at the mip and layer the first output declares.
  std::vector<std::string> targets;
  Subresources at;
  for (const ResourceUse& output : ctx.declaration().outputs) {
    if (output.use != Use::color_attachment)
      throw GraphError(ctx.pass() + ": a full-screen pass writes colour attachments only, not '" + output.resource +
                       "'");
    if (targets.empty()) at = output.range;
    targets.push_back(output.resource);
  }
  ctx.begin_rendering(targets, "", at.base_mip, at.base_layer);
  ctx.bind_pipeline(specialization);
  ctx.push_declared();
  if (!constants.empty()) ctx.push_constants(constants.data(), uint32_t(constants.size()));
  vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
  ctx.end_rendering();
}

}  // namespace nightcap
