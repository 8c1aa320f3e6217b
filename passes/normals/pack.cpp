// normals.pack: world normals from the 10-bit G-buffer repacked as 8-bit best-fit normals
// with roughness (R8G8B8A8_UNORM), the form SSR and the later screen-space passes read, using
// the table of normals.bfn_lut. Where nothing was drawn (RT1 holds 0, which 0.5n + 0.5 of a
// unit normal never is) it writes the codes of the zero vector, 128, and the roughness: so a
// cleared G-buffer packs to the clear value, and frame.md's "never skipped" gives way to the
// geometry stage's rule.

#include <cmath>

#include "passes/core/context.h"
#include "passes/normals/kinds.h"
#include "passes/normals/stage.h"

namespace nightcap {
namespace {

// The stored vector, before normalising: 8-bit codes · 2/255 − 1.
std::array<double, 3> stored_vector(const TexelValues& t) {
  return {t.codes[0] * (2.0 / 255.0) - 1, t.codes[1] * (2.0 / 255.0) - 1, t.codes[2] * (2.0 / 255.0) - 1};
}

const KindRegistration kPackedNormal({
    .kind = kinds::packed_normal,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_stored_normal(stored_vector(t), out);
          out["roughness"] = t.raw[3];
        },
    .draw = [](const TexelValues& t, const KindFrame&) { return stored_normal_picture(stored_vector(t)); },
    .measure = KindMeasure::unit_vector,
});

}  // namespace

PassDecl normals_pack_pass() {
  ImageDecl packed{VK_FORMAT_R8G8B8A8_UNORM, kinds::packed_normal};
  packed.clear.color = {{128.0f / 255.0f, 128.0f / 255.0f, 128.0f / 255.0f, 0.0f}};
  return PassDecl("normals.pack", PassType::graphics)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("normals.bfn_lut", Use::sampled)
      .write("normals.packed", Use::color_attachment, packed)
      .skip_when_cleared({"gbuffer.normal", "gbuffer.material"})
      .fullscreen("normals/pack.frag");
}

}  // namespace nightcap
