// gi.volume (frame.md, [000][001]): low-frequency irradiance around the camera, for the
// composite's indirect diffuse on static and moving surfaces alike: cells³ cells of gi.plan's
// grid, each the irradiance about every normal as spherical harmonics of bands 0–2, gathered from
// the reflection probes' irradiance and the sky's with the sky's visibility from above
// (volume.comp); volume_layout.glsl.h says how a cell is stored. The volume is history: a frame
// carries the previous one over (a transfer copy) and gathers only the boxes gi.plan lists in
// gi.refresh (cells scrolled in, cells of probes captured this frame; all of them on a frame
// without history, after a cut, when the sky changed). Skipped without a sun (no sky: the
// composite's indirect diffuse is its ambient term) and with `--set gi.enabled=0`, when the
// composite lights every point with the sky's irradiance as before; cleared when gi.plan planned
// nothing (the sky switched off).
#include <array>
#include <cstring>

#include "passes/core/context.h"
#include "passes/core/history_name.h"
#include "passes/frame/scene_resources.h"
#include "passes/gi/stage.h"
#include "passes/gi/volume_layout.h"
#include "passes/lighting/shared_params.h"
#include "passes/probes/capture_layout.h"
#include "passes/sky/ibl.glsl.h"

namespace nightcap {

namespace kinds {
// A texel of the GI volume: four of a cell's 27 spherical-harmonic coefficients (volume_layout.glsl.h).
inline constexpr ResourceKind sh_irradiance_cells{"sh_irradiance_cells"};
}  // namespace kinds

namespace {

// `inspect pixel X Y --slice Z` on gi.volume: the cell of texel (X, Y, Z), its size and the bands
// the composite reads (gi.volume_data), its 9 coefficients per colour and the irradiance over π
// they give about each axis, as the composite reads it at the cell's centre.
void describe_cell(const std::vector<std::vector<double>>& texels, std::span<const uint8_t> record,
                   nlohmann::ordered_json& out) {
  std::array<glm::dvec3, 9> c{};
  for (int j = 0; j < 27; ++j) c[size_t(j / 3)][j % 3] = texels.at(size_t(j / 4)).at(size_t(j % 4));
  if (record.size() == sizeof(GpuGiVolume)) {
    GpuGiVolume volume;
    std::memcpy(&volume, record.data(), sizeof volume);
    out["cell_metres"] = volume.origin.w;
    out["bands_read"] = volume.evaluation.x == 1 ? "0-1" : "0-2";
  }
  nlohmann::ordered_json coefficients = nlohmann::ordered_json::array();
  for (const glm::dvec3& k : c) coefficients.push_back({k.x, k.y, k.z});
  out["coefficients"] = coefficients;
  nlohmann::ordered_json about = nlohmann::ordered_json::object();
  const std::pair<const char*, glm::dvec3> axes[] = {{"+x", {1, 0, 0}},  {"-x", {-1, 0, 0}}, {"+y", {0, 1, 0}},
                                                     {"-y", {0, -1, 0}}, {"+z", {0, 0, 1}},  {"-z", {0, 0, -1}}};
  for (const auto& [name, n] : axes) {
    const std::array<double, 9> y = sh_basis_of(n);
    glm::dvec3 e(0.0);
    for (int i = 0; i < 9; ++i) e += c[size_t(i)] * y[size_t(i)];
    e = glm::max(e, glm::dvec3(0.0));
    about[name] = {e.x, e.y, e.z};
  }
  out["irradiance_over_pi"] = about;
}

const KindRegistration kShIrradianceCells({
    .kind = kinds::sh_irradiance_cells,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["coefficients"] = {t.raw[0], t.raw[1], t.raw[2], t.raw[3]};
        },
    // The first block holds each cell's band-0 coefficient per colour: its mean irradiance.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::relative,
                              {std::max(t.raw[0], 0.0), std::max(t.raw[1], 0.0), std::max(t.raw[2], 0.0)}};
        },
    .over_output = false,
    .slice_blocks = SliceBlocks{kGiVolumeTexels, "gi.volume_data", describe_cell},
});

}  // namespace

PassDecl gi_volume_pass() {
  ImageDecl volume{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::sh_irradiance_cells};
  volume.size.mode = SizeRule::Mode::square_param;
  volume.size.param = "cells";
  volume.depth = kGiVolumeTexels;
  volume.depth_param = "cells";
  return PassDecl("gi.volume", PassType::compute)
      .read("gi.volume_data", Use::uniform_buffer)
      .read("gi.refresh", Use::host)
      .read("gi.plan", Use::host)
      .read("sky.irradiance", Use::storage_read)
      .read("shadow.topdown_data", Use::uniform_buffer)
      .read("shadow.topdown", Use::sampled)
      .read_optional("probes.slots", Use::storage_read)
      .read_optional("probes.irradiance", Use::storage_read)
      .read_previous("gi.volume", Use::sampled)
      .write("gi.volume", Use::storage_write, volume)
      .param(gi_cells_param())
      .param(probe_fade_param())
      .compare("gi.volume",
               ComparisonContract::floats(0x1p-24, 0x1p-10, "sums of 9 products, each stored as the nearest half"))
      .needs("sun")
      .can_disable("the GI volume disabled by settings (indirect diffuse from the sky's irradiance)", "gi")
      .push_constants<GiVolumeConstants>()
      .shader("gi/volume.comp")
      .run([](PassContext& ctx) {
        const auto plans = host_records<GiPlan>(ctx.host("gi.plan"));
        if (plans.empty()) {  // no sky to gather (gi.plan says why): nothing the composite reads
          ctx.clear_layers("gi.volume", 0, 1, ctx.desc("gi.volume").clear);
          return;
        }
        const GiPlan& plan = plans.front();
        const auto boxes = host_records<GiBox>(ctx.host("gi.refresh"));
        if (plan.cells != ctx.desc("gi.volume").extent.width)
          throw GraphError("gi.volume: gi.plan places " + std::to_string(plan.cells) + " cells a side in a volume of " +
                           std::to_string(ctx.desc("gi.volume").extent.width));
        if (plan.refresh == uint32_t(GiRefresh::kept)) ctx.copy_resource(previous("gi.volume"), "gi.volume");
        if (boxes.empty()) return;
        const bool probes = ctx.reads("probes.slots") && ctx.reads("probes.irradiance");
        const uint32_t slots = probes ? uint32_t(ctx.host("probes.slots").size() / sizeof(GpuProbeSlot)) : 0u;
        const glm::ivec3 origin(plan.origin_cell[0], plan.origin_cell[1], plan.origin_cell[2]);
        ctx.bind_pipeline();
        ctx.push_declared();
        for (const GiBox& box : boxes) {
          const glm::ivec3 low(box.min[0], box.min[1], box.min[2]);
          const glm::ivec3 size(int32_t(box.size[0]), int32_t(box.size[1]), int32_t(box.size[2]));
          if (glm::any(glm::lessThan(low, origin)) ||
              glm::any(glm::greaterThan(low + size, origin + int32_t(plan.cells))))
            throw GraphError("gi.volume: gi.refresh lists a box outside the volume gi.plan places");
          ctx.push_constants(GiVolumeConstants{
              glm::ivec4(low, int32_t(slots)), glm::uvec4(box.size[0], box.size[1], box.size[2], probes ? 1u : 0u),
              glm::vec4(float(ctx.param_float("probe_fade_metres")), 0.0f, 0.0f, 0.0f)});
          vkCmdDispatch(ctx.cmd(), group_count(box.size[0], kGiVolumeGroupSide),
                        group_count(box.size[1], kGiVolumeGroupSide), group_count(box.size[2], kGiVolumeGroupSide));
        }
      });
}

}  // namespace nightcap
