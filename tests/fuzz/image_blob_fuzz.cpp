// Image blobs (multi-part OpenEXR); the input is described in image_blob_input.h. A blob the
// reader accepts must decode to the raw size of the expected format and extent, and encoding the
// result again (zip) must read back to the same bytes: every code survives the round trip.
#include <vector>

#include "captures/blob_codec.h"
#include "tests/fuzz/image_blob_input.h"
#include "tests/fuzz/scratch_file.h"

namespace nc = nightcap;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto input = nc::fuzz::parse_image_blob_input({data, size});
  if (!input) return -1;
  const auto file = nc::fuzz::write_scratch("blob.exr", input->blob);
  std::vector<uint8_t> raw;
  try {
    raw = nc::read_image_blob(file, input->format, input->extent);
  } catch (const nc::CaptureError&) {
    return 0;
  }
  if (raw.size() != nc::raw_image_bytes(input->format, input->extent)) __builtin_trap();
  const auto again = nc::fuzz::scratch_folder() / "again.exr";
  nc::write_image_blob(again, input->format, input->extent, raw, {nc::ExrCompression::zip, 1}, 0);
  if (nc::read_image_blob(again, input->format, input->extent) != raw) __builtin_trap();
  return 0;
}
