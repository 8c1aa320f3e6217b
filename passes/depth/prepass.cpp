// depth.prepass: depth of the opaque occluders before the G-buffer, so the G-buffer pass
// shades each pixel about once. Reversed-Z: cleared to 0 (infinitely far), GREATER passes.
#include "passes/core/context.h"
#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/frame/draw_scene.h"
#include "passes/scene/stencil_tags.h"

namespace nightcap {
namespace {

// Reversed-Z with an infinite far plane: device depth d is znear / distance; none for 0 (nothing
// drawn).
double distance_or_zero(double device_depth, const KindFrame& frame) {
  return device_depth > 0.0 ? frame.znear / device_depth : 0.0;
}

const KindRegistration kDepthStencil({
    .kind = kinds::depth_stencil,
    .describe =
        [](const TexelValues& t, const KindFrame& frame, nlohmann::ordered_json& out) {
          out["device_depth"] = t.raw[0];
          const double metres = distance_or_zero(t.raw[0], frame);
          out["linear_m"] =
              metres > 0 ? nlohmann::ordered_json(metres) : nlohmann::ordered_json("infinite (nothing drawn)");
          if (t.raw.size() > 1) describe_stencil_tag(uint32_t(t.codes.at(0)), out);
        },
    .draw =
        [](const TexelValues& t, const KindFrame& frame) {
          return TexelPicture{TexelPicture::Scale::distance, {distance_or_zero(t.raw[0], frame), 0, 0}};
        },
    .draw_stencil = stencil_colour,
    .measure = KindMeasure::depth,
});

}  // namespace

PassDecl depth_prepass_pass() {
  ImageDecl depth{VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil};
  depth.clear.depthStencil = {0.0f, 0};
  return PassDecl("depth.prepass", PassType::graphics)
      .read("frame.views", Use::storage_read)
      .as("views")
      .read("scene.geometry", Use::storage_read)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("draws.depth.prepass", Use::storage_read)
      .as("draws")
      .write("scene.depth", Use::depth_attachment, depth)
      .raster(RasterState::per_draw(VK_CULL_MODE_BACK_BIT))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER, true))
      .needs("opaque_geometry")
      .shader("depth/prepass.vert")
      .run([](PassContext& ctx) {
        ctx.begin_rendering();
        ctx.bind_pipeline();
        ctx.push_declared();
        draw_scene(ctx, "draws.depth.prepass", [](uint32_t, const GpuMaterial&) {});
        ctx.end_rendering();
      });
}

}  // namespace nightcap
