// sky.multiscattering (frame.md section 4, `sky.luts`): Hillaire's (2020) LUT of the light
// scattered more than once, per height and light zenith, as multiscattering.comp computes it.
// 32×32 by default, Hillaire's size (frame.md's class size is 256×256: the LUT is smooth, and
// the benchmark's table of size against error decides: 64×64 gains nothing). 16×16 directions,
// where Hillaire takes 8×8: against a converged double reference his 64 directions were 6.2% off
// (relative L1) and 47% at altitude, where the limb's dense air is a thin band of directions; 256
// are 2.7% for 3.5 times the time, paid once per atmosphere. Depends on the atmosphere alone: copied
// from the previous frame's unless sky.atmosphere says it changed. Skipped with no directional
// light.
#include "passes/core/context.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_multiscattering_pass() {
  return sky_pass("sky.multiscattering", PassType::compute)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read("sky.transmittance", Use::sampled)
      .sampler("sky.transmittance", bilinear_clamp_sampler())
      .read_previous("sky.multiscattering", Use::sampled)
      .write("sky.multiscattering", Use::storage_write, sky_lut_image(kinds::sky_lut))
      .param_int("width", 32, 2, 1024, "texels across: the cosine of the light's zenith angle")
      .param_int("height", 32, 2, 1024, "texels down: the height")
      // At most 32 + 32² + 32²·60 loop iterations a texel: lavapipe ends a shader's loops after 65535.
      .param_int("samples", 20, 1, 60, "steps along each direction's ray")
      .param_int("directions", 16, 1, 32, "directions per side of the sphere's grid (their square in all)")
      .push_constants<SkyLutConstants>()
      .shader("sky/multiscattering.comp")
      .run([](PassContext& ctx) { dispatch_sky_lut(ctx, "sky.multiscattering"); });
}

}  // namespace nightcap
