// Where NaNs and Infs appear in a capture: the passes that wrote them first. What can hold one:
// float colour images, the float depth of D32_SFLOAT and of D32_SFLOAT_S8_UINT's depth aspect,
// and the f32/f64 fields of buffers whose recorded schema declares them (a buffer without a
// schema is not read).
//
// A pass is an origin ("born") when it wrote a non-finite value and every input it read held
// finite values only. The version it started from of a resource it modified is one of those
// inputs, so each non-finite value of its outputs was finite (or absent) before it: born there.
// A pass that read a non-finite value and wrote one, into the resource it read or a fresh one,
// passed it on and is not named: a blur spreads one NaN over its neighbours, a resolve copies it
// into another resource, and a capture that records per pass, not per texel, cannot tell that
// from a second birth. A second birth there shows once the first origin is fixed.
// A version that no searched pass wrote (scene data; with one frame searched, a history written
// in an earlier frame) and that holds non-finite values "came in" at the first pass that reads it.
//
// So when the search finds nothing, no float value of any version of the searched frames is a
// NaN or an Inf; and the first origin it finds is the first place one appears. The capture
// records each pass's outputs, not each draw's, so a pass is the finest origin it can name.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

struct NonFiniteTexel {
  uint32_t x = 0, y = 0, slice = 0, mip = 0, layer = 0;  // slice: z of a 3D image
  uint32_t pixel_x = 0, pixel_y = 0;                     // the output pixel over it
  std::vector<double> values;                            // its channels (depth: 1), as format.h decodes them
};

struct NonFiniteField {
  uint64_t element = 0;
  std::string field;  // component_name(): "position.y", "model[13]"
  double value = 0.0;
};

// The non-finite values of one version that appeared there.
struct NonFiniteValues {
  const ResourceRecord* resource = nullptr;
  uint64_t count = 0;  // texels (with any channel non-finite) or buffer field components
  // Up to the limit, in the order of the raw bytes: an image's by mip, layer, slice, row, column;
  // a buffer's by element, then field.
  std::vector<NonFiniteTexel> texels;
  std::vector<NonFiniteField> fields;
};

struct NanOrigin {
  enum class How { born, came_in };
  How how = How::born;
  size_t frame_position = 0;  // in the frames searched over
  size_t pass_index = 0;      // in that frame's passes
  // born: the pass's outputs with values born there, in the pass's order; came_in: the inputs it
  // read that hold non-finite values and that no searched pass wrote.
  std::vector<NonFiniteValues> resources;
};

// The raw bytes of a version (Capture::load, or bytes in memory).
using LoadVersion = std::function<std::vector<uint8_t>(const ResourceRecord&)>;

// Every origin in the frames (or only in frames[*only_frame]), in execution order, frame by
// frame; empty when no NaN or Inf appears. Loads each distinct version at most once and keeps
// none. `limit`: how many texels or fields each resource lists. Schemas of buffer inputs come
// from the output of any frame that wrote the same version.
std::vector<NanOrigin> find_nan_origins(std::span<const FrameRecord> frames, std::optional<size_t> only_frame,
                                        const LoadVersion& load, size_t limit);

}  // namespace nightcap
