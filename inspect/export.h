// Resources written to files: the values as float OpenEXR (what the pass wrote, decoded to
// numbers), the picture through visualise.h as PNG.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

#include "captures/capture.h"
#include "inspect/decode.h"

namespace nightcap {

struct ValuesExr {
  // HALF channels (what RenderDoc writes; exact for half formats, nearest for wider ones)
  // instead of FLOAT.
  bool half = false;
  bool compressed = true;  // ZIP; false: uncompressed, the fastest to write and to read
};

// One subimage with every channel as FLOAT (or HALF), as format.h decodes it (UNORM in
// [0, 1], sRGB linearised, integer codes as their values): R, G, B, A in order, or Z and S for
// depth and stencil. Throws InspectError when the file cannot be written.
void write_values_exr(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
                      const Subimage& subimage, const ValuesExr& options = {});

}  // namespace nightcap
