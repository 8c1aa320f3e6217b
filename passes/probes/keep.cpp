// probes.keep: this frame's probes.array and probes.irradiance start as the previous frame's (a
// transfer copy of each, every slot and mip), which probes.convert and probes.irradiance then write
// this frame's captures into: both are history, and a frame that captures nothing (the two skipped)
// keeps the probes captured before. probes.array: RGBA16F, two square `size` layers per slot of
// probes.plan (paraboloid.glsl.h: the upper and the lower hemisphere; the seeds' 512×256 texture
// per probe, its halves as layers so that each clamps at its own edge), kProbeArrayMips mips, level
// m prefiltered for roughness m / (kProbeArrayMips − 1). Without history (the first frame, a camera
// cut) the previous array is cleared, and probes.plan captures every probe in range. Skipped in a
// scene without probes.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/probes/paraboloid.glsl.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"
#include "passes/sky/ibl.glsl.h"

namespace nightcap {

namespace kinds {
// A probe's hemisphere (paraboloid.glsl.h), a layer of probes.array: radiance by direction.
inline constexpr ResourceKind probe_paraboloid{"probe_paraboloid"};
}  // namespace kinds

namespace {

KindInfo paraboloid_kind() {
  KindInfo info{.kind = kinds::probe_paraboloid};
  info.describe = [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
    out["radiance"] = {t.raw[0], t.raw[1], t.raw[2]};
  };
  info.layer_directions = LayerDirections{
      [](uint32_t layer, double u, double v) {
        const glm::dvec3 d = paraboloid_direction(layer % 2, glm::dvec2(u, v) * 2.0 - 1.0);
        return std::array<double, 3>{d.x, d.y, d.z};
      },
      [](uint32_t slot, const std::array<double, 3>& direction) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(direction[0], direction[1], direction[2]));
        const glm::dvec2 uv = paraboloid_point(d) * 0.5 + 0.5;
        return std::pair<uint32_t, std::array<double, 2>>{2 * slot + paraboloid_hemisphere(d), {uv.x, uv.y}};
      }};
  return info;
}

const KindRegistration kProbeParaboloid(paraboloid_kind());

}  // namespace

PassDecl probes_keep_pass() {
  ImageDecl array{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::probe_paraboloid};
  array.size.mode = SizeRule::Mode::square_param;
  array.size.param = "size";
  array.layers = 2 * kProbeSlots;
  array.mips = kProbeArrayMips;
  return PassDecl("probes.keep", PassType::compute)
      .read_previous("probes.array", Use::sampled)
      .read_previous("probes.irradiance", Use::storage_read)
      .write("probes.array", Use::storage_write, array)
      .write("probes.irradiance", Use::storage_write, BufferDecl(kinds::buffer, kProbeSlots * sizeof(GpuSkyIrradiance)))
      .layout("probes.irradiance", NC_SCHEMA_OF(GpuSkyIrradiance, NC_GPU_SKY_IRRADIANCE_FIELDS))
      .param_int("size", 256, 32, 2048, "texels on a side of each hemisphere of a probe (the seeds' 512×256: 256)")
      .can_disable("reflection probes disabled by settings", "probes")
      .needs("reflection_probes")
      .run([](PassContext& ctx) {
        ctx.copy_resource(previous("probes.array"), "probes.array");
        ctx.copy_resource(previous("probes.irradiance"), "probes.irradiance");
      });
}

}  // namespace nightcap
