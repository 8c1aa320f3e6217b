// sky.cubemap (frame.md section 4, `sky.luts`' sky cubemap with mips, B10G11R11_UFLOAT): the
// sky around the camera as a cube map, each texel sky.view's radiance along its direction, and
// its mip chain down to 1×1 by 2×2 means, as cubemap.comp computes them. What sky.irradiance
// and sky.specular read (and, to come, the probes). 128 texels a face by default. Follows the
// camera and the light: computed when sky.atmosphere's record says the sky seen from the camera
// changed, copied from the previous frame's otherwise. Skipped with the sky's other passes.
#include "passes/core/context.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_cubemap_pass() {
  return sky_pass("sky.cubemap", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read("sky.view", Use::sampled)
      .sampler("sky.view", bilinear_clamp_sampler())
      .read_previous("sky.cubemap", Use::sampled)
      .write("sky.cubemap", Use::storage_write, sky_cube_image(VK_FORMAT_B10G11R11_UFLOAT_PACK32, 0))
      .level_mips("sky.cubemap", {-1, 0})  // the level above the one written (level 0: unused), and that one
      .param_int("size", 128, 1, 4096, "texels on a side of each face of level 0")
      .push_constants<SkyCubeConstants>()
      .shader("sky/cubemap.comp")
      .run([](PassContext& ctx) {
        // Each level reads the one above: in order.
        dispatch_sky_cube_levels(
            ctx, "sky.cubemap", [](uint32_t) { return 0u; }, true);
      });
}

}  // namespace nightcap
