// The full-screen pattern: one triangle over the output, everything else from the declaration.
#include "passes/core/context.h"

namespace nightcap {
namespace {

// The one mip or layer a declared range selects, or -1 for all of them.
int single(uint32_t base, uint32_t count) { return count == 1 ? int(base) : -1; }

}  // namespace

void record_fullscreen(PassContext& ctx, std::span<const uint8_t> constants,
                       const std::vector<int32_t>& specialization) {
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
        bindings.push_back(Binding::texture(ctx.slot(input.bound_name()), input.bound_name(), ctx.nearest_clamp(),
                                            ViewAspect::natural, single(input.range.base_mip, input.range.mip_count),
                                            single(input.range.base_layer, input.range.layer_count)));
        break;
      case Use::host:
        continue;  // read on the CPU when recording, not by the shader
      default:
        throw GraphError(ctx.pass() + ": a full-screen pass cannot bind '" + input.resource + "' for that use");
    }
  }
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
  ctx.push(bindings);
  if (!constants.empty()) ctx.push_constants(constants.data(), uint32_t(constants.size()));
  vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
  ctx.end_rendering();
}

}  // namespace nightcap
