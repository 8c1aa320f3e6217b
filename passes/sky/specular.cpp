// sky.specular: sky.cubemap prefiltered with GGX for image-based specular light (Karis 2013's
// split sum), a perceptual roughness per mip, as specular.comp computes it: mip m holds roughness
// m / 5 over 6 mips, 64 texels a face at mip 0 by default, and 128 samples a texel at mip 1,
// 4× as many each mip down (as many texels fewer: each mip costs the same). RGBA16F: the
// prefiltered radiance stays within half a half-float ULP of its sum, which B10G11R11's 5-bit
// blue mantissa would not (tests/unit/sky_ibl_test.cpp). Computed when sky.cubemap is, copied
// from the previous frame's otherwise; skipped with the sky's other passes.
#include "passes/core/context.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_specular_pass() {
  return sky_pass("sky.specular", PassType::compute)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read("sky.cubemap", Use::sampled)
      .sampler("sky.cubemap", trilinear_clamp_sampler())
      .read_previous("sky.specular", Use::sampled)
      .write("sky.specular", Use::storage_write, sky_cube_image(VK_FORMAT_R16G16B16A16_SFLOAT, kSkySpecularMips))
      .level_mips("sky.specular", {0})
      .param_int("size", 64, 32, 4096, "texels on a side of each face of mip 0 (at least 32: six mips)")
      .param_int("samples", 128, 1, 255,
                 "GGX samples per texel of mip 1; each later mip 4× as many (mip 5: 256×, within lavapipe's "
                 "65535 loop iterations)")
      .push_constants<SkyCubeConstants>()
      .shader("sky/specular.comp")
      .run([](PassContext& ctx) {
        const uint32_t samples = uint32_t(ctx.param_int("samples"));
        // A mip has a quarter of the texels of the one above: four times the samples cost the same.
        // The levels read sky.cubemap alone: no order among them.
        dispatch_sky_cube_levels(
            ctx, "sky.specular", [&](uint32_t level) { return level == 0 ? 1u : samples << (2 * (level - 1)); }, false);
      });
}

}  // namespace nightcap
