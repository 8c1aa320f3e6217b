// sky.atmosphere (CPU): the atmosphere the sky's LUTs are computed for, as a record the sky's
// passes read (atmosphere.glsl.h, schema atmosphere_schema), from the pass's parameters. It reads
// its own previous record (history: empty on frame 0 and after a camera cut) and sets `changed`
// when this frame's differs: x for the atmosphere, on which sky.transmittance and
// sky.multiscattering alone depend; y for the sky seen from the camera (the atmosphere, the
// frame's directional light and its radiance, the camera's height), on which sky.view and the
// cube maps depend. Each is computed on a frame whose flag is set and copied from the previous
// frame's otherwise (a walking camera under a fixed sun keeps them all), and the record in the
// capture says which. (The LUT passes' own parameters cannot change
// between a render's frames: a Renderer's settings are fixed.) Skipped with no directional light to light a sky
// (frame.constants' sun): the record is then empty, and the sky's other passes write zeros.
#include "passes/sky/atmosphere.h"

#include <cmath>
#include <cstddef>
#include <cstring>

#include "passes/core/context.h"
#include "passes/core/history_name.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/sky/luts.h"
#include "passes/sky/stage.h"

namespace nightcap {

BufferSchema atmosphere_schema() { return NC_SCHEMA_OF(GpuAtmosphere, NC_GPU_ATMOSPHERE_FIELDS); }

GpuAtmosphere earth_atmosphere(const AtmosphereFactors& factors) {
  const auto per_km = [](double a, double b, double c, double scale) {
    return glm::vec3(float(a * scale), float(b * scale), float(c * scale));
  };
  GpuAtmosphere a{};
  a.rayleigh = glm::vec4(per_km(5.802e-3, 13.558e-3, 33.1e-3, factors.rayleigh), 8.0f);
  a.mie_scattering = glm::vec4(per_km(3.996e-3, 3.996e-3, 3.996e-3, factors.mie), 1.2f);
  a.mie_extinction = glm::vec4(per_km(4.40e-3, 4.40e-3, 4.40e-3, factors.mie), float(factors.mie_g));
  a.ozone = glm::vec4(per_km(0.650e-3, 1.881e-3, 0.085e-3, factors.ozone), 25.0f);
  a.radii = glm::vec4(6360.0f, 6460.0f, 15.0f, float(factors.ground_albedo));
  return a;
}

PassDecl sky_atmosphere_pass() {
  return sky_pass("sky.atmosphere", PassType::cpu)
      .read("frame.constants", Use::host)
      .read_previous("sky.atmosphere", Use::host)
      .write("sky.atmosphere", Use::host, BufferDecl{kinds::buffer})
      .layout("sky.atmosphere", atmosphere_schema())
      .param_float("rayleigh", 1.0, 0.0, 100.0, "density of the air's molecules (Rayleigh scattering), Earth's = 1")
      .param_float("mie", 1.0, 0.0, 100.0, "density of aerosols (Mie scattering and absorption), Earth's clear day = 1")
      .param_float("ozone", 1.0, 0.0, 100.0, "density of ozone (absorption), Earth's = 1")
      .param_float("mie_g", 0.8, -0.999, 0.999, "asymmetry of the aerosols' phase function (Cornette-Shanks g)")
      .param_float("ground_albedo", 0.3, 0.0, 1.0, "the ground's albedo in the multiple scattering LUT")
      .run([](PassContext& ctx) {
        // No directional light to light a sky, or the sky switched off: no record, what skipping
        // the pass leaves (a replay runs the skipped pass to check that).
        const GpuFrameConstants frame = host_records<GpuFrameConstants>(ctx.host("frame.constants")).at(0);
        if (!ctx.flag("enabled") || frame.sun_direction.w == 0.0f) {
          ctx.output("sky.atmosphere").clear();
          return;
        }
        GpuAtmosphere atmosphere =
            earth_atmosphere({ctx.param_float("rayleigh"), ctx.param_float("mie"), ctx.param_float("ozone"),
                              ctx.param_float("mie_g"), ctx.param_float("ground_albedo")});
        // Whole metres: the sky changes by far less than a metre's worth between them, and a
        // walking camera's height wanders by millimetres every frame.
        atmosphere.light = glm::vec4(glm::vec3(frame.sun_direction), std::round(frame.camera_world.y));
        atmosphere.light_radiance = frame.sun_radiance;
        const std::span<const uint8_t> previous_bytes = ctx.host(previous("sky.atmosphere"));
        bool same_air = false, same_view = false;
        if (previous_bytes.size() == sizeof(GpuAtmosphere)) {
          GpuAtmosphere before;
          std::memcpy(&before, previous_bytes.data(), sizeof before);
          // The air is everything up to `light`; the view adds the light and the camera's height.
          same_air = std::memcmp(&before, &atmosphere, offsetof(GpuAtmosphere, light)) == 0;
          same_view =
              same_air && before.light == atmosphere.light && before.light_radiance == atmosphere.light_radiance;
        }
        atmosphere.changed = glm::uvec4(same_air ? 0u : 1u, same_view ? 0u : 1u, 0u, 0u);
        ctx.store("sky.atmosphere", std::span<const GpuAtmosphere>(&atmosphere, 1));
      });
}

}  // namespace nightcap
