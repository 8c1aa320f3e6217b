// What the ambient-occlusion chain's passes share, and how inspect and the report read its images
// (passes/ao/kinds.h).
#include "passes/ao/chain.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "passes/ao/chain.glsl.h"
#include "passes/ao/kinds.h"
#include "passes/core/context.h"

namespace nightcap {
namespace {

void describe_visibility(double visibility, nlohmann::ordered_json& out) {
  out["visibility"] = visibility;
  out["occlusion"] = 1.0 - visibility;
  out["cone_half_angle_deg"] = std::asin(std::sqrt(std::clamp(visibility, 0.0, 1.0))) * 180.0 / M_PI;
}

// `b` over its length, or null where it is (nearly) the zero vector: nothing was drawn.
nlohmann::ordered_json direction(const std::array<double, 3>& b, double shortest) {
  const double length = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (length <= shortest) return nullptr;
  return nlohmann::ordered_json::array({b[0] / length, b[1] / length, b[2] / length});
}

// The visibility, as grey: white is unoccluded.
TexelPicture draw_visibility(const TexelValues& t, const KindFrame&) {
  return TexelPicture{TexelPicture::Scale::display, {t.raw[3], t.raw[3], t.raw[3]}};
}

const KindRegistration kAoBent({
    .kind = kinds::ao_bent,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_visibility(t.raw[3], out);
          // The zero vector is codes 128: a length under 0.01.
          out["bent_normal"] = direction({t.raw[0] * 2.0 - 1.0, t.raw[1] * 2.0 - 1.0, t.raw[2] * 2.0 - 1.0}, 0.1);
        },
    .draw = draw_visibility,
});

// The frames an ao.history texel averages: the length of its rgb.
double history_frames(const TexelValues& t) {
  return std::sqrt(t.raw[0] * t.raw[0] + t.raw[1] * t.raw[1] + t.raw[2] * t.raw[2]);
}

const KindRegistration kAoHistory({
    .kind = kinds::ao_history,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          describe_visibility(t.raw[3], out);
          out["frames"] = history_frames(t);
          out["bent_normal"] = direction({t.raw[0], t.raw[1], t.raw[2]}, 0.5);
        },
    // A texel of no frames (nothing drawn there) stores visibility 0, which is no value rather
    // than full occlusion: white, as ao.bent shows nothing drawn.
    .draw =
        [](const TexelValues& t, const KindFrame& frame) {
          return history_frames(t) < 0.5 ? TexelPicture{TexelPicture::Scale::display, {1.0, 1.0, 1.0}}
                                         : draw_visibility(t, frame);
        },
});

}  // namespace

PassDecl ao_chain_pass(std::string name) {
  return PassDecl(std::move(name), PassType::compute).can_disable("ambient occlusion disabled by settings", "ao");
}

ImageDecl ao_bent_image() {
  ImageDecl bent{VK_FORMAT_R8G8B8A8_UNORM, kinds::ao_bent};
  bent.size.mode = SizeRule::Mode::output_half;
  bent.clear.color = {{kAoZeroComponent, kAoZeroComponent, kAoZeroComponent, 1.0f}};  // the zero vector, unoccluded
  return bent;
}

ImageDecl ao_history_image() {
  ImageDecl history{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::ao_history};
  history.size.mode = SizeRule::Mode::output_half;
  return history;  // cleared to zero: no frames
}

}  // namespace nightcap
