// Where a NaN or an Inf was born in a frame: the first pass whose float outputs hold non-finite
// texels that the version it started from held finite. A pass that reads a NaN and passes it on
// is not its origin. The capture records each pass's outputs, not each draw's, so a pass is the
// finest origin it can name.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "inspect/session.h"

namespace nightcap {

struct NonFiniteTexel {
  uint32_t x = 0, y = 0, slice = 0, mip = 0, layer = 0;  // slice: z of a 3D image
  uint32_t pixel_x = 0, pixel_y = 0;                     // the output pixel over it
  std::vector<double> values;                            // its channels, as format.h decodes them
};

// The texels of one output that became NaN or ±Inf in its pass.
struct NonFiniteBirths {
  const ResourceRecord* resource = nullptr;
  uint64_t count = 0;
  std::vector<NonFiniteTexel> first;  // up to the limit, by mip, layer, slice, row, column
};

struct NanOrigin {
  size_t pass_index = 0;                 // in the frame's passes
  std::vector<NonFiniteBirths> outputs;  // each float output with any, in the pass's order
};

// Walks the session's current frame in execution order; nullopt when no pass made a NaN or an
// Inf. `limit`: how many texels each output lists.
std::optional<NanOrigin> find_nan_origin(InspectSession& session, size_t limit);

}  // namespace nightcap
