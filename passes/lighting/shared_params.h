// The lighting parameters the reflection probes' captures (probes.light) and the GI volume share
// with the frame's passes, so a face or a cell is lit as the frame would light the same point:
// each declared once here and set under its frame pass's name for all (`--set
// lighting.composite.ambient=…` sets the probes' too; ParamDecl::group).
#pragma once

#include <glm/glm.hpp>

#include "passes/core/params.h"

namespace nightcap {

// lighting.composite's indirect light and sky.
inline ParamDecl ambient_param() {
  return ParamDecl::real("ambient", 0.02, 0.0, 1e6,
                         "uniform ambient radiance (a stand-in for the indirect light to come)")
      .shared_by("lighting.composite");
}
inline ParamDecl night_sky_param() {
  return ParamDecl::real("sky", 0.004, 0.0, 1e6, "radiance of the night sky where nothing was drawn")
      .shared_by("lighting.composite");
}
inline ParamDecl multiple_scattering_param() {
  return ParamDecl::boolean("multiple_scattering", true,
                            "add the energy single scattering loses to the image-based specular (Fdez-Agüera 2019)")
      .shared_by("lighting.composite");
}
// How the reflection probes' boxes weigh them, for the composite's reflections and the GI
// volume's gather alike (probes/reflection.glsl).
inline ParamDecl probe_fade_param() {
  return ParamDecl::real("probe_fade_metres", 4.0, 0.0, 1000.0,
                         "a reflection probe's weight falls to 0 over this distance inside its box's faces")
      .shared_by("lighting.composite");
}
// The radiances the two set: a cool night ambient and a deep blue sky.
inline glm::vec4 ambient_radiance(double ambient) {
  const float a = float(ambient);
  return {a * 0.8f, a * 0.9f, a * 1.2f, 0.0f};
}
inline glm::vec4 sky_radiance(double sky) {
  const float s = float(sky);
  return {s * 0.5f, s * 0.7f, s * 1.6f, 0.0f};
}

// lighting.deferred's direct light (direct_light.glsl).
inline ParamDecl min_roughness_param() {
  return ParamDecl::real("min_roughness", 0.03, 0.0, 1.0,
                         "roughness floor: keeps point highlights finite in half floats")
      .shared_by("lighting.deferred");
}
inline ParamDecl tube_samples_param() {
  return ParamDecl::integer("tube_samples", 8, 1, 256, "samples along each tube light for its diffuse term")
      .shared_by("lighting.deferred");
}

}  // namespace nightcap
