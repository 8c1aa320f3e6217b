// One output pixel followed through a frame: every pass that wrote a screen-space resource there
// (depth and stencil included), with the texel before and after it, in execution order. The
// capture records each pass's outputs, not each draw's, so a pass is the finest step: two draws
// of one pass that both touched the pixel show as one write.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inspect/session.h"

namespace nightcap {

struct PixelWrite {
  size_t pass_index = 0;
  const ResourceRecord* before = nullptr;  // nullptr: the pass made the resource's first version
  const ResourceRecord* after = nullptr;
  TexelAddress texel;    // in the resource (before and after have the same extent)
  bool changed = false;  // the texel differs from before (always true without a before)
};

// A resource is followed when one of its mips has the output's size or a power-of-two fraction of
// it (half-resolution targets, pyramids); tables and 1x1 values are not screen positions. Every
// mip of layer 0 is followed. `only`: one resource's writes (empty: all). Throws InspectError for
// a pixel outside the output or an `only` the frame does not write.
std::vector<PixelWrite> pixel_history(InspectSession& session, uint32_t x, uint32_t y, const std::string& only);

}  // namespace nightcap
