// A buffer in the capture's report, read by the schema its writer recorded, as `inspect buffer`
// reads it (inspect/decode.h): a record (one element) as a table of its fields, a list as its
// count and its first entries, a draw list as its draws and triangles; without a schema, its size.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "captures/capture.h"

namespace nightcap {

// The entries of a list shown: enough to see what it holds, few enough for a page of sixty
// passes; `inspect buffer` shows any other.
inline constexpr uint64_t kListEntriesShown = 8;

struct BufferFigure {
  std::string html;   // what stands above the figure's caption
  bool wide = false;  // a table with long rows (a column per field, matrices): wider than a picture
};

// `raw`: the buffer's bytes, read only where `schema` is set. Values are exact: integers as they
// are, floats in the fewest digits that read back as the same float (or double, for f64 fields).
BufferFigure buffer_figure(const ResourceRecord& record, const BufferSchema* schema, std::span<const uint8_t> raw);

}  // namespace nightcap
