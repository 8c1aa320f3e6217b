// sky.transmittance (frame.md section 4, `sky.luts`): the atmosphere's transmittance from any
// height along any direction that does not meet the ground, to the atmosphere's top, as
// transmittance.comp computes it. 256×64 by default, the size frame.md and Hillaire (2020) give.
// Depends on the atmosphere alone: copied from the previous frame's unless sky.atmosphere says
// it changed. Skipped with no directional light.
#include "passes/core/context.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_transmittance_pass() {
  return sky_pass("sky.transmittance", PassType::compute)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read_previous("sky.transmittance", Use::sampled)
      .write("sky.transmittance", Use::storage_write, sky_lut_image(kinds::sky_lut))
      .param_int("width", 256, 2, 4096, "texels across: the distance to the atmosphere's top")
      .param_int("height", 64, 2, 4096, "texels down: the height")
      .param_int("samples", 256, 1, 65535, "midpoint samples of the extinction along each texel's ray")
      .push_constants<SkyLutConstants>()
      .shader("sky/transmittance.comp")
      .run([](PassContext& ctx) { dispatch_sky_lut(ctx, "sky.transmittance"); });
}

}  // namespace nightcap
