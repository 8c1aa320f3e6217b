// LightOccluders: shadow.cull's test of a caster against the occluders the sun sees, in
// shadow.distant_occluders.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "passes/frame/hierarchy.h"

namespace nightcap::shadow_cull {

// shadow.distant_occluders as an occlusion buffer from the sun [004 §2.2.3]: level 0 of the
// distant shadow, holding only what every cascade surely draws too (shadow.distant_plan's
// occluders). A caster whose box, seen from the sun, lies wholly behind its depth over the box's
// footprint grown by a texel each side, by more than `slope` times two texels of depth, draws no
// texel of a cascade: the occluder's depth is less wherever the caster's could land. Sampled at
// texel centres, so an opening narrower than a texel (25 cm at the default 256 m level) between
// occluders is not seen; the slope margin covers a surface's depth changing between centres.
// Empty (hides nothing) when the distant levels did not run.
class LightOccluders {
 public:
  LightOccluders(std::span<const uint8_t> data, std::span<const uint8_t> depth, double slope);

  // Whether the camera-relative box is wholly behind the occluders, seen from the sun.
  bool hides(const Box& box) const;

 private:
  uint32_t resolution_ = 0;
  glm::dmat4 light_from_world_{1.0};
  double margin_ = 0.0;
  std::vector<std::vector<float>> mips_;
};

}  // namespace nightcap::shadow_cull
