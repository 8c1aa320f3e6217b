// `export --half --uncompressed`: what RenderDoc writes for a render target, checked against the
// capture's blobs by their byte layout and read back with OpenEXR.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>
#include <half.h>

#include <cstring>

#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

struct HalfImage {
  Imf::Compression compression = Imf::ZIP_COMPRESSION;
  std::vector<std::string> channels;
  std::vector<std::vector<Imath::half>> planes;
};

HalfImage read_half_exr(const fs::path& file, int width, int height) {
  Imf::InputFile in(file.c_str());
  HalfImage image;
  image.compression = in.header().compression();
  Imf::FrameBuffer buffer;
  for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c) {
    EXPECT_EQ(c.channel().type, Imf::HALF) << c.name();
    image.channels.push_back(c.name());
  }
  image.planes.resize(image.channels.size(), std::vector<Imath::half>(size_t(width) * height));
  for (size_t c = 0; c < image.channels.size(); ++c)
    buffer.insert(image.channels[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(image.planes[c].data()),
                                                sizeof(Imath::half), sizeof(Imath::half) * width));
  in.setFrameBuffer(buffer);
  in.readPixels(0, height - 1);
  return image;
}

TEST(InspectExport, HalfUncompressedTargetsHoldTheStoredValues) {
  const fs::path capture_path = shared_capture("city", kCity);
  const Capture capture = Capture::open(capture_path);
  const PassRecord& gbuffer = pass_named(capture.frame(0), "gbuffer.opaque");
  const fs::path dir = scratch("export-half");
  const Inspected run = inspect(
      capture_path, "goto gbuffer.opaque --json; export gbuffer.motion --half --uncompressed -o " +
                        (dir / "motion.exr").string() + " --json; export gbuffer.albedo --half --uncompressed -o " +
                        (dir / "albedo.exr").string() + " --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;

  // R16G16_SFLOAT: the stored halves, bit for bit.
  const std::vector<uint8_t> motion = capture.load(output_named(gbuffer, "gbuffer.motion"));
  const HalfImage m = read_half_exr(dir / "motion.exr", 320, 180);
  EXPECT_EQ(m.compression, Imf::NO_COMPRESSION);
  ASSERT_EQ(m.channels, (std::vector<std::string>{"G", "R"}));  // OpenEXR lists channels by name
  for (size_t i = 0; i < 320 * 180; ++i)
    for (int c = 0; c < 2; ++c) {
      uint16_t stored;
      std::memcpy(&stored, motion.data() + 4 * i + 2 * c, 2);
      ASSERT_EQ(m.planes[c == 0 ? 1 : 0][i].bits(), stored) << i;
    }

  // A2B10G10R10: each 10-bit code / 1023, rounded to the nearest half.
  const std::vector<uint8_t> albedo = capture.load(output_named(gbuffer, "gbuffer.albedo"));
  const HalfImage a = read_half_exr(dir / "albedo.exr", 320, 180);
  ASSERT_EQ(a.channels, (std::vector<std::string>{"A", "B", "G", "R"}));
  for (size_t i = 0; i < 320 * 180; ++i) {
    uint32_t word;
    std::memcpy(&word, albedo.data() + 4 * i, 4);
    const float r = float(word & 1023) / 1023.0f, g = float((word >> 10) & 1023) / 1023.0f;
    const float b = float((word >> 20) & 1023) / 1023.0f, alpha = float(word >> 30) / 3.0f;
    ASSERT_EQ(a.planes[3][i].bits(), Imath::half(r).bits()) << i;
    ASSERT_EQ(a.planes[2][i].bits(), Imath::half(g).bits()) << i;
    ASSERT_EQ(a.planes[1][i].bits(), Imath::half(b).bits()) << i;
    ASSERT_EQ(a.planes[0][i].bits(), Imath::half(alpha).bits()) << i;
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
