#include "tests/e2e/damaged_capture.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "captures/capture.h"

namespace nightcap::test {
namespace fs = std::filesystem;

namespace {

void overwrite_with(const fs::path& file, char fill) {
  const auto size = fs::file_size(file);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << std::string(size, fill);
}

}  // namespace

std::set<std::string> damage_every_blob(const fs::path& folder) {
  const Capture capture = Capture::open(folder);
  std::set<std::string> done, damaged;
  for (const FrameRecord& frame : capture.manifest().frames)
    for (const PassRecord& pass : frame.passes) {
      for (const auto* side : {&pass.inputs, &pass.outputs})
        for (const ResourceRecord& r : *side) {
          if (!done.insert(r.blob).second) continue;
          if (r.raw_bytes() == 0) continue;
          damaged.insert(r.blob);
          std::vector<uint8_t> raw(r.raw_bytes(), 0);
          raw[0] = 1;  // a low bit of the first texel's first channel: valid in any format
          if (r.is_buffer)
            write_buffer_blob(folder / r.blob, raw, 3);
          else
            write_image_blob(folder / r.blob, *format_info(r.format), r.extent, raw, {ExrCompression::zip});
        }
      for (const ShaderRecord& s : pass.shaders)
        for (const std::string& blob : {s.blob, s.source_blob})
          if (done.insert(blob).second) {
            overwrite_with(folder / blob, 'x');
            damaged.insert(blob);
          }
    }
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder / "blobs")) ++files;
  EXPECT_EQ(files, done.size()) << "a blob the manifest does not name";
  return damaged;
}

}  // namespace nightcap::test
