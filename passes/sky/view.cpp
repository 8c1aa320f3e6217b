// sky.view (frame.md section 4, `sky.luts`): the sky's radiance around the camera, per view
// direction relative to the frame's directional light, as view.comp computes it; what the
// composite draws where nothing was. 192×108 by default, Hillaire's (2020) size. Follows the
// camera and the light: computed on a frame whose sky.atmosphere record says the sky seen from
// the camera changed (changed.y), copied from the previous frame's otherwise. Skipped with no directional light (the
// composite then draws its constant sky).
#include "passes/core/context.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_view_pass() {
  return sky_march_pass("sky.view")
      .read_previous("sky.view", Use::sampled)
      .write("sky.view", Use::storage_write, sky_lut_image(kinds::sky_view))
      .param_int("width", 192, 2, 4096, "texels across: the azimuth from the light")
      .param_int("height", 108, 2, 4096, "texels down: the zenith angle, half above the horizon")
      .param_int("samples", 32, 1, 4096, "steps along each texel's view ray")
      .push_constants<SkyLutConstants>()
      .shader("sky/view.comp")
      .run([](PassContext& ctx) { dispatch_sky_lut(ctx, "sky.view"); });
}

}  // namespace nightcap
