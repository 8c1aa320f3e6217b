// probes.gbuffer: the G-buffer of each captured probe face (probes.views, six per captured
// probe), drawn with the frame's own surface shaders (gbuffer/opaque.vert and .frag) from
// draws.probes, one layer of each target per face: the surfaces of the face's range
// (probes.face_draws). The targets are gbuffer.opaque's in format and meaning (motion is
// written but no pass reads it), each a 2D array of kProbeSlots × 6 layers of `face_size`
// texels a side (a reset captures every slot); the layers past this frame's faces are cleared,
// so what the capture records does not depend on earlier frames. Depth is its own
// (probes.depth, D32, reversed-Z like scene.depth, no prepass: written here). Skipped
// when no probe is captured this frame (probes.views empty) and in a scene without probes.
#include "passes/core/context.h"
#include "passes/frame/scene_resources.h"
#include "passes/gbuffer/draw_surfaces.h"
#include "passes/gbuffer/kinds.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"

namespace nightcap {
namespace {

// Reversed-Z device depth of a probe face (0: nothing drawn), from its view's near plane.
constexpr ResourceKind kProbeDepthKind{"probe_depth"};

const KindRegistration kProbeDepth({
    .kind = kProbeDepthKind,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["device_depth"] = t.raw[0];
          out["drawn"] = t.raw[0] > 0.0;
        },
    .measure = KindMeasure::depth,
});

const std::vector<std::string> kTargets = {"probes.gbuffer.albedo",   "probes.gbuffer.normal",
                                           "probes.gbuffer.material", "probes.gbuffer.motion",
                                           "probes.gbuffer.emissive", "probes.gbuffer.occlusion"};

ImageDecl face_layers(VkFormat format, ResourceKind kind) {
  ImageDecl image{format, kind};
  image.size.mode = SizeRule::Mode::square_param;
  image.size.param = "face_size";
  image.layers = kProbeSlots * 6;
  return image;
}

void draw_faces(PassContext& ctx) {
  const auto faces = host_records<GpuProbeFace>(ctx.host("probes.face_draws"));
  const uint32_t layers = kProbeSlots * 6;
  if (faces.size() > layers)
    throw GraphError("probes.gbuffer: probes.face_draws holds " + std::to_string(faces.size()) + " faces, over " +
                     std::to_string(layers));
  for (uint32_t layer = 0; layer < faces.size(); ++layer) {
    ctx.begin_rendering(kTargets, "probes.depth", 0, layer);
    if (faces[layer].draws > 0) draw_surfaces(ctx, "draws.probes", {faces[layer].first_draw, faces[layer].draws});
    ctx.end_rendering();
  }
  const uint32_t used = uint32_t(faces.size());
  if (used == layers) return;
  for (const std::string& target : kTargets) ctx.clear_layers(target, used, layers - used, ctx.desc(target).clear);
  ctx.clear_layers("probes.depth", used, layers - used, ctx.desc("probes.depth").clear);
}

}  // namespace

PassDecl probes_gbuffer_pass() {
  ImageDecl unoccluded = face_layers(VK_FORMAT_R8_UNORM, kinds::occlusion);
  unoccluded.clear.color = {{1.0f, 0.0f, 0.0f, 0.0f}};
  ImageDecl depth = face_layers(VK_FORMAT_D32_SFLOAT, kProbeDepthKind);
  depth.clear.depthStencil = {0.0f, 0};
  return surface_drawing_pass("probes.gbuffer", "probes.views", "draws.probes")
      .read("probes.face_draws", Use::host)
      .write("probes.gbuffer.albedo", Use::color_attachment,
             face_layers(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::colour))
      .write("probes.gbuffer.normal", Use::color_attachment,
             face_layers(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal))
      .write("probes.gbuffer.material", Use::color_attachment, face_layers(VK_FORMAT_R8G8B8A8_UNORM, kinds::material))
      .write("probes.gbuffer.motion", Use::color_attachment, face_layers(VK_FORMAT_R16G16_SFLOAT, kinds::motion))
      .write("probes.gbuffer.emissive", Use::color_attachment,
             face_layers(VK_FORMAT_B10G11R11_UFLOAT_PACK32, kinds::hdr_colour))
      .write("probes.gbuffer.occlusion", Use::color_attachment, unoccluded)
      .write("probes.depth", Use::depth_attachment, depth)
      .param(probe_face_size())
      // GREATER_OR_EQUAL as gbuffer.opaque: of two coplanar surfaces (a road's markings on it) the
      // later drawn shows, as in the frame.
      .depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER_OR_EQUAL, true))
      .skip_when_cleared({"probes.views"})
      .shader("gbuffer/opaque.vert")
      .shader("gbuffer/opaque.frag")
      .can_disable("reflection probes disabled by settings", "probes")
      .needs("reflection_probes")
      .run(draw_faces);
}

}  // namespace nightcap
