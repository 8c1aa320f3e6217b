// The constructors of the sky's passes (frame.md section 4, `sky.luts`, carried out as four
// passes: the atmosphere's record, then a pass per LUT, so that each LUT is recorded, replayed and
// kept on its own), which the frame's assembly (passes/assembly/registry.cpp) puts in the frame.
#pragma once

#include "passes/core/pass.h"

namespace nightcap {

PassDecl sky_atmosphere_pass();
PassDecl sky_transmittance_pass();
PassDecl sky_multiscattering_pass();
PassDecl sky_view_pass();
PassDecl sky_aerial_perspective_pass();
PassDecl sky_cubemap_pass();
PassDecl sky_irradiance_pass();
PassDecl sky_specular_pass();

}  // namespace nightcap
