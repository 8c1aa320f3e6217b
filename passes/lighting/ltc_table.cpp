// lighting.ltc_table (CPU): the committed LTC table of passes/lighting/ltc/ggx_table.h as two
// images lighting.tiled reads, so the capture records the table with the frame and a replay of
// lighting.tiled needs nothing but its recorded inputs. lighting.ltc_inverse (RGBA32F) holds M⁻¹
// (m00, m02, m20, m22) and lighting.ltc_magnitude (RG32F) the magnitudes (norm, fresnel); texel
// (x, y) is entry y·N + x: roughness across, view down (ltc.h). Never skipped; nothing to build.
#include <cstring>

#include "passes/core/context.h"
#include "passes/lighting/ltc/ggx_table.h"
#include "passes/lighting/stage.h"

namespace nightcap {

PassDecl lighting_ltc_table_pass() {
  constexpr uint32_t n = ltc::kGgxTableSize;
  static_assert(sizeof(ltc::kGgxInverse) == n * n * 4 * sizeof(float));
  static_assert(sizeof(ltc::kGgxMagnitude) == n * n * 2 * sizeof(float));
  ImageDecl inverse{VK_FORMAT_R32G32B32A32_SFLOAT, kinds::lookup_table};
  inverse.size = {SizeRule::Mode::absolute, n, n, ""};
  ImageDecl magnitude{VK_FORMAT_R32G32_SFLOAT, kinds::lookup_table};
  magnitude.size = inverse.size;
  return PassDecl("lighting.ltc_table", PassType::cpu)
      .write("lighting.ltc_inverse", Use::host, inverse)
      .write("lighting.ltc_magnitude", Use::host, magnitude)
      .run([](PassContext& ctx) {
        auto copy = [&](const char* resource, const float* values, size_t bytes) {
          std::vector<uint8_t>& out = ctx.output(resource);
          out.resize(bytes);
          std::memcpy(out.data(), values, bytes);
        };
        copy("lighting.ltc_inverse", ltc::kGgxInverse, sizeof(ltc::kGgxInverse));
        copy("lighting.ltc_magnitude", ltc::kGgxMagnitude, sizeof(ltc::kGgxMagnitude));
      });
}

}  // namespace nightcap
