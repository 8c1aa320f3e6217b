// sky.aerial_perspective (frame.md section 4, `sky.luts`' aerial perspective): the air between
// the camera and each point it sees, as aerial_perspective.comp computes it: a 32×32×32 volume
// over the view frustum (Hillaire's 2020 size), its slices reaching kSkyAerialDistanceKm along
// each view ray; per km of a slice's length, the in-scattered radiance in rgb and the optical
// depth of the mean transmittance in alpha (Hillaire stores the totals: per km, the near slices
// interpolate 3.9 times closer to the reference; docs/benchmark.md). What the
// composite applies to every surface. Follows the camera: computed every frame (its view moves
// with it). Skipped with the sky's other passes; with no record it holds its clear value, no air.
#include "passes/core/context.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_aerial_perspective_pass() {
  ImageDecl volume{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::aerial_perspective};
  volume.size.mode = SizeRule::Mode::params;
  volume.size.param = "width";
  volume.size.height_param = "height";
  volume.depth_param = "slices";
  return sky_march_pass("sky.aerial_perspective")
      .read("frame.views", Use::uniform_buffer)
      .write("sky.aerial_perspective", Use::storage_write, volume)
      .param_int("width", 32, 2, 1024, "texels across the screen")
      .param_int("height", 32, 2, 1024, "texels down the screen")
      // At most 256 + 256·64 loop iterations a ray: lavapipe ends a shader's loops after 65535.
      .param_int("slices", 32, 2, 256, "slices along each view ray, thin near the camera")
      .param_int("samples", 1, 1, 64, "steps through each slice")
      .push_constants<SkyLutConstants>()
      .shader("sky/aerial_perspective.comp")
      .run([](PassContext& ctx) { dispatch_sky_lut(ctx, "sky.aerial_perspective"); });
}

}  // namespace nightcap
