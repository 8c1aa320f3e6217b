// shadow.topdown (frame.md, [001]): the static scene seen from straight above, a D16 map of
// `resolution` texels a side whose depth is the height of the topmost static opaque surface over
// each texel (0 at the scene's top, 1 at its bottom or where nothing is; shadow.topdown_plan
// says where the map lies and why it is redrawn). The map is history: a frame that does not
// redraw it carries the previous frame's over (a transfer copy). D16, as the seeds' map: over a
// scene 200 m tall a step is 3 mm, below the metre a lookup is pushed along its normal.
// Read by topdown.glsl: whether the sky is straight above a point (lighting.composite's and
// probes.light's sky light). Skipped without a sun (no sky) or with the sky switched off
// (`--set sky.enabled=0`): nothing reads the sky's visibility then.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/caster_draw.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"
#include "passes/shadow/topdown_layout.h"

namespace nightcap {

namespace kinds {
// Heights seen from above: depth 0 at the static scene's top, 1 at its bottom or where nothing is.
inline constexpr ResourceKind height_from_above{"height_from_above"};
}  // namespace kinds

namespace {

const KindRegistration kHeightFromAbove({
    .kind = kinds::height_from_above,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["depth"] = t.raw[0];
          out["covered"] = t.raw[0] < 1.0;
          // shadow.topdown_plan's top and bottom turn it into metres.
          out["height_share"] = 1.0 - t.raw[0];
        },
    // Height as brightness, against the map's tallest: its roofs white, the ground near black.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          const double height = 1.0 - t.raw[0];
          return TexelPicture{TexelPicture::Scale::relative, {height, height, height}};
        },
    .over_output = false,
    .measure = KindMeasure::depth,
});

}  // namespace

PassDecl shadow_topdown_pass() {
  ImageDecl map{VK_FORMAT_D16_UNORM, kinds::height_from_above};
  map.size.mode = SizeRule::Mode::square_param;
  map.size.param = "resolution";
  map.clear.depthStencil = {1.0f, 0};
  return PassDecl("shadow.topdown", PassType::graphics)
      .read("scene.geometry", Use::storage_read)
      .read("draws.shadow.topdown", Use::storage_read)
      .as("draws")
      .read("shadow.topdown_data", Use::uniform_buffer)
      .read_previous("shadow.topdown", Use::sampled)
      .read("scene.geometry", Use::index_buffer)
      .read("scene.materials", Use::host)
      .read("shadow.topdown_plan", Use::host)
      .write("shadow.topdown", Use::depth_attachment, map)
      .param(topdown_resolution())
      .raster(RasterState::per_draw(VK_CULL_MODE_NONE))
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_LESS, true))
      .can_disable("sky visibility disabled by settings (the sky's diffuse light reaches everywhere)")
      .needs("sun")
      .push_constants<CasterConstants>()
      .shader("shadow/topdown.vert")
      .run([](PassContext& ctx) {
        const auto plan = host_records<TopdownPlan>(ctx.host("shadow.topdown_plan")).at(0);
        if (plan.refresh == uint32_t(TopdownRefresh::kept)) {
          ctx.copy_layer(previous("shadow.topdown"), 0, "shadow.topdown", 0);
          return;
        }
        // Redrawn whole: the attachment's clear (1, nothing) is its start.
        ctx.begin_rendering({}, "shadow.topdown");
        bind_casters(ctx, 0);
        draw_casters(ctx, "draws.shadow.topdown", {});
        ctx.end_rendering();
      });
}

}  // namespace nightcap
