// Buffer blobs (zstd frames). Input: the size the manifest would expect (4 bytes, little-endian,
// up to 1 MiB) then the blob's bytes. A blob the reader accepts must decode to exactly that many
// bytes, and encoding those bytes again must read back to the same bytes.
#include <cstring>
#include <vector>

#include "captures/blob_codec.h"
#include "tests/fuzz/scratch_file.h"

namespace nc = nightcap;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr size_t kHeader = 4;
  if (size < kHeader) return -1;
  uint32_t expected = 0;
  std::memcpy(&expected, data, kHeader);
  expected %= 1u << 20;
  const auto file = nc::fuzz::write_scratch("blob.bin.zst", {data + kHeader, size - kHeader});
  std::vector<uint8_t> raw;
  try {
    raw = nc::read_buffer_blob(file, expected);
  } catch (const nc::CaptureError&) {
    return 0;
  }
  if (raw.size() != expected) __builtin_trap();
  const auto again = nc::fuzz::scratch_folder() / "again.bin.zst";
  nc::write_buffer_blob(again, raw, 1);
  if (nc::read_buffer_blob(again, expected) != raw) __builtin_trap();
  return 0;
}
