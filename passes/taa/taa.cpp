// taa (frame.md section 7): temporal anti-aliasing. frame.constants jitters the camera by a
// sub-pixel offset each frame (passes/frame/jitter.h); this pass blends the frame's lit colour
// into its history, reprojected along gbuffer.motion and clipped to the pixel's neighbourhood
// (taa.comp), and writes taa.resolved (RGBA16F), which bloom, exposure and tonemap read, and
// taa.history, which the next frame reprojects. The graph clears the history on frame 0, a
// camera cut or a resize, and the resolve then starts from the current frame.
//
// frame.md says taa is never skipped. `--set taa.enabled=0` turns it off for comparison and
// debugging: frame.constants stops jittering and this pass copies lighting.lit into taa.resolved
// as it is and clears the history, so every other output is what a frame without TAA computes.
// The pass still runs because post reads taa.resolved in either case: the assembly wires the
// frame once.
#include "passes/core/context.h"
#include "passes/frame/jitter.h"
#include "passes/taa/kinds.h"
#include "passes/taa/stage.h"
#include "passes/taa/taa.glsl.h"

namespace nightcap {
namespace {

// Both kinds hold HDR colour in rgb: described and drawn as hdr_colour is, alpha aside.
void describe_colour(const TexelValues& t, nlohmann::ordered_json& out) {
  kind_info(kinds::hdr_colour).describe(t, KindFrame{}, out);
}
TexelPicture draw_colour(const TexelValues& t, const KindFrame& frame) {
  return kind_info(kinds::hdr_colour).draw(t, frame);
}

const KindRegistration kTaaResolved({
    .kind = kinds::taa_resolved,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_colour(t, out);
          out["history_clipped"] = t.raw.at(3) > 0.0;
          out["clip_removed"] = t.raw.at(3);
        },
    .draw = draw_colour,
    .light = true,
});

const KindRegistration kTaaHistory({
    .kind = kinds::taa_history,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_colour(t, out);
          const double frames = t.raw.at(3);
          out["frames"] = frames;
          // The resolve that wrote it gave the current frame 1/frames of the result.
          out["history_weight"] = frames >= 1.0 ? 1.0 - 1.0 / frames : 0.0;
        },
    .draw = draw_colour,
    .light = true,
});

}  // namespace

PassDecl taa_pass() {
  return PassDecl("taa", PassType::compute)
      .read("lighting.lit", Use::sampled)
      .read_previous("taa.history", Use::sampled)
      .sampler("taa.history", bilinear_clamp_sampler())  // the history input, taa.history@previous
      .read("gbuffer.motion", Use::sampled)
      .read("motion.mask", Use::sampled)
      .read_previous("motion.mask", Use::sampled)
      .write("taa.resolved", Use::storage_write, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::taa_resolved})
      .write("taa.history", Use::storage_write, ImageDecl{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::taa_history})
      .param(taa_enabled_param())
      .param_int("frames", 16, 1, 256,
                 "the most frames the history averages: a still pixel's n-th frame weighs 1/n up to 1/frames")
      .param_int("masked_frames", 2, 1, 256,
                 "the same where motion.mask is set now or was a frame ago (moving objects, hair, foliage)")
      .choice("clip", kTaaClipVariance, {{"variance", kTaaClipVariance}, {"minmax", kTaaClipMinMax}},
              "the box the history is clipped to, in YCoCg: the 3×3 neighbourhood's mean ± gamma standard "
              "deviations (Salvi 2016), or its minimum and maximum")
      .param_float("gamma", 1.0, 0.1, 8.0, "the variance box's half size, in standard deviations")
      .param_float("masked_gamma", 0.75, 0.1, 8.0, "the same where motion.mask is set (now or a frame ago)")
      .flag("clip_still", false,
            "clip the history of still pixels too (moving under 1/64 pixel, unmasked now and a frame ago): light "
            "that changes under a still camera is followed at once instead of fading in over `frames` frames, "
            "and sub-pixel detail flickers")
      .shader("taa/taa.comp")
      .push_constants<TaaConstants>()
      .run([](PassContext& ctx) {
        if (!ctx.flag("enabled")) {
          ctx.copy_resource("lighting.lit", "taa.resolved");
          ctx.clear_layers("taa.history", 0, 1, VkClearValue{});
          return;
        }
        ctx.bind_pipeline();
        ctx.push_declared();
        ctx.push_constants(TaaConstants{float(ctx.param_int("frames")), float(ctx.param_int("masked_frames")),
                                        float(ctx.param_float("gamma")), float(ctx.param_float("masked_gamma")),
                                        uint32_t(ctx.param_int("clip")), ctx.flag("clip_still") ? 1u : 0u});
        const ImageExtent size = ctx.desc("taa.resolved").extent;
        vkCmdDispatch(ctx.cmd(), group_count(size.width, kTaaTile), group_count(size.height, kTaaTile), 1);
      });
}

}  // namespace nightcap
