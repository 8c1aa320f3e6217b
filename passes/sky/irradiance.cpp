// sky.irradiance: the sky's irradiance for indirect diffuse light, as 9 spherical-harmonic
// coefficients per colour (Ramamoorthi and Hanrahan 2001) projected from a level of sky.cubemap of
// at most 32 texels a face (a band-2 projection needs no more), as irradiance.comp computes them.
// The composite reads it by each pixel's normal. Computed when sky.cubemap is, copied from the
// previous frame's otherwise; skipped with the sky's other passes.
#include "passes/core/context.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

PassDecl sky_irradiance_pass() {
  return sky_pass("sky.irradiance", PassType::compute)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read("sky.cubemap", Use::sampled)
      .read_previous("sky.irradiance", Use::storage_read)
      .write("sky.irradiance", Use::storage_write, BufferDecl(kinds::buffer, sizeof(GpuSkyIrradiance)))
      .layout("sky.irradiance", NC_SCHEMA_OF(GpuSkyIrradiance, NC_GPU_SKY_IRRADIANCE_FIELDS))
      .compare("sky.irradiance",
               ComparisonContract::floats(1e-6, 1e-4, "a float sum of 6144 texels in a fixed order per invocation"))
      .push_constants<SkyCubeConstants>()
      .shader("sky/irradiance.comp")
      .run([](PassContext& ctx) {
        const ImageExtent cube = ctx.desc("sky.cubemap").extent;
        uint32_t level = 0;
        while (level + 1 < cube.mips && mip_size(cube.width, level) > kSkyIrradianceFace) ++level;
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(SkyCubeConstants{0u, has_atmosphere(ctx), 0u, level});
        vkCmdDispatch(ctx.cmd(), 1, 1, 1);
      });
}

}  // namespace nightcap
