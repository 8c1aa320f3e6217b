#include "passes/sky/luts.h"

#include <cstring>

#include "passes/core/context.h"
#include "passes/sky/atmosphere.glsl.h"
#include "passes/sky/ibl.glsl.h"
#include "passes/sky/kinds.h"
#include "passes/sky/view_uv.h"

namespace nightcap {
namespace {

// An RGB table or cube map of radiance or transmittance, drawn relative to its largest value.
KindInfo sky_table(ResourceKind kind) {
  return KindInfo({
      .kind = kind,
      .describe =
          [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
            out["rgb"] = {t.raw.at(0), t.raw.at(1), t.raw.at(2)};
          },
      .draw =
          [](const TexelValues& t, const KindFrame&) {
            return TexelPicture{TexelPicture::Scale::relative, {t.raw.at(0), t.raw.at(1), t.raw.at(2)}};
          },
      .over_output = false,
  });
}
const KindRegistration kSkyLut(sky_table(kinds::sky_lut));
const KindRegistration kSkyCube(sky_table(kinds::sky_cube));
const KindRegistration kSkyView([] {
  KindInfo info = sky_table(kinds::sky_view);
  info.directions = DirectionLookup{"sky.atmosphere",
                                    [](const std::array<double, 3>& direction, std::span<const uint8_t> record,
                                       uint32_t width, uint32_t height) -> std::optional<std::array<double, 2>> {
                                      GpuAtmosphere atmosphere;
                                      if (record.size() != sizeof atmosphere) return std::nullopt;
                                      std::memcpy(&atmosphere, record.data(), sizeof atmosphere);
                                      return sky_view_uv(atmosphere, direction, width, height);
                                    }};
  return info;
}());
const KindRegistration kAerialPerspective({
    .kind = kinds::aerial_perspective,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["in_scattered_per_km"] = {t.raw.at(0), t.raw.at(1), t.raw.at(2)};
          out["optical_depth_per_km"] = t.raw.at(3);
        },
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::relative, {t.raw.at(0), t.raw.at(1), t.raw.at(2)}};
        },
    // Froxels: its texels lie over the output, so `inspect pixel X Y --slice K` reads the one under a pixel.
    .over_output = true,
});

}  // namespace

PassDecl sky_pass(std::string name, PassType type) {
  return PassDecl(std::move(name), type)
      .can_disable("sky disabled by settings (the composite draws its constant sky)", "sky")
      .needs("sun");
}

PassDecl sky_march_pass(std::string name) {
  return sky_pass(std::move(name), PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("sky.atmosphere", Use::uniform_buffer)
      .read("sky.transmittance", Use::sampled)
      .sampler("sky.transmittance", bilinear_clamp_sampler())
      .read("sky.multiscattering", Use::sampled)
      .sampler("sky.multiscattering", bilinear_clamp_sampler());
}

ImageDecl sky_lut_image(ResourceKind kind) {
  ImageDecl lut{VK_FORMAT_R16G16B16A16_SFLOAT, kind};
  lut.size.mode = SizeRule::Mode::params;
  lut.size.param = "width";
  lut.size.height_param = "height";
  return lut;
}

uint32_t has_atmosphere(const PassContext& ctx) { return ctx.host("sky.atmosphere").empty() ? 0u : 1u; }

ImageDecl sky_cube_image(VkFormat format, uint32_t mips) {
  ImageDecl cube{format, kinds::sky_cube};
  cube.size.mode = SizeRule::Mode::square_param;
  cube.size.param = "size";
  cube.mips = mips;
  cube.layers = 6;
  cube.cube = true;
  return cube;
}

void dispatch_sky_cube_levels(PassContext& ctx, const std::string& cube,
                              const std::function<uint32_t(uint32_t level)>& samples, bool in_order) {
  ctx.bind_pipeline();
  const ImageExtent extent = ctx.desc(cube).extent;
  const uint32_t atmosphere = has_atmosphere(ctx);
  for (uint32_t level = 0; level < extent.mips; ++level) {
    const uint32_t side = mip_size(extent.width, level);
    ctx.push_declared(level);
    ctx.push_constants(SkyCubeConstants{level, atmosphere, samples(level), 0u});
    vkCmdDispatch(ctx.cmd(), group_count(side, kSkyGroupSide), group_count(side, kSkyGroupSide), 6);
    if (in_order) ctx.storage_barrier();
  }
}

void dispatch_sky_lut(PassContext& ctx, const std::string& lut) {
  const ImageExtent size = ctx.desc(lut).extent;
  SkyLutConstants constants{uint32_t(ctx.param_int("samples")), 0u, has_atmosphere(ctx)};
  if (ctx.declaration().find_param("directions")) constants.directions = uint32_t(ctx.param_int("directions"));
  ctx.bind_pipeline();
  ctx.push_declared();
  ctx.push_constants(constants);
  vkCmdDispatch(ctx.cmd(), group_count(size.width, kSkyGroupSide), group_count(size.height, kSkyGroupSide), 1);
}

}  // namespace nightcap
