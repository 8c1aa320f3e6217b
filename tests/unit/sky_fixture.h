// What the sky's unit tests share: sky.transmittance and sky.multiscattering at their default
// sizes, as the frame computes them before the sky's other passes.
#pragma once

#include <vector>

#include "passes/core/history_name.h"
#include "passes/sky/kinds.h"
#include "passes/sky/stage.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {

class SkyLutTest : public GpuTest {
 protected:
  static IsolatedInput lut(const std::vector<uint8_t>& bytes, uint32_t w, uint32_t h) {
    return image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::sky_lut, w, h, bytes);
  }

  struct Luts {
    IsolatedInput transmittance, multiscattering;
    std::vector<uint8_t> multiscattering_bytes;
  };

  // The two LUTs for the record `atmosphere`, each from a previous frame's zeros.
  static Luts compute_luts(const IsolatedInput& atmosphere) {
    const IsolatedRun transmittance =
        run(sky_transmittance_pass(),
            {{"sky.atmosphere", atmosphere},
             {previous("sky.transmittance"), lut(std::vector<uint8_t>(256 * 64 * 8, 0), 256, 64)}},
            1, 1);
    Luts luts{lut(*transmittance.outputs.at("sky.transmittance"), 256, 64), {}, {}};
    const IsolatedRun multiscattering =
        run(sky_multiscattering_pass(),
            {{"sky.atmosphere", atmosphere},
             {"sky.transmittance", luts.transmittance},
             {previous("sky.multiscattering"), lut(std::vector<uint8_t>(32 * 32 * 8, 0), 32, 32)}},
            1, 1);
    luts.multiscattering_bytes = *multiscattering.outputs.at("sky.multiscattering");
    luts.multiscattering = lut(luts.multiscattering_bytes, 32, 32);
    return luts;
  }
};

}  // namespace nightcap::test
