// normals.pack: world normals from the 10-bit G-buffer repacked as 8-bit best-fit normals
// with roughness (R8G8B8A8_UNORM), the form SSR and the later screen-space passes read, using
// the table of normals.bfn_lut. Never skipped (frame.md).

#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"

namespace nightcap {

PassDecl normals_pack_pass() {
  return PassDecl("normals.pack", PassType::graphics)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("normals.bfn_lut", Use::sampled)
      .write("normals.packed", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::packed_normal})
      .fullscreen("normals/pack.frag");
}

}  // namespace nightcap
