// What covers a pixel: the geometry pass (gbuffer.opaque) run again from its recorded inputs
// with one more colour target, the index of the draw that wrote each pixel. Rendering and the
// capture carry nothing for it; the draw's record then names the instance, the mesh (its index
// range) and the material.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "captures/capture.h"
#include "passes/core/device.h"
#include "passes/frame/gpu_types.h"

namespace nightcap {

// Per output pixel, row by row: the draw that covers it, as an index into the geometry pass's
// draw list, plus one; 0 where no draw covers it (sky).
struct DrawIdImage {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> ids;
};

// The pass that pick replays.
inline constexpr const char* kPickedPass = "gbuffer.opaque";

// Throws InspectError when the frame's geometry pass did not run, ShaderError when its recorded
// fragment shader cannot take the extra output, CaptureError for a damaged capture.
DrawIdImage render_draw_ids(GpuDevice& gpu, const Capture& capture, const FrameRecord& frame);

struct Pick {
  uint32_t draw = 0;  // index into the pass's draw list
  GpuDraw record;     // that draw, as the capture holds it
  GpuMaterial material;
};
// nullopt where no draw covers (x, y). Throws InspectError for a pixel outside the image.
std::optional<Pick> pick(const DrawIdImage& ids, const Capture& capture, const FrameRecord& frame, uint32_t x,
                         uint32_t y);

}  // namespace nightcap
