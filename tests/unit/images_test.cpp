// Images go through the image module that nightcap_core loads on first use: what it decodes
// matches OpenImageIO read directly (linked by this test, not by core), from a file or from
// memory, any channel count becomes RGBA8, an embedded glTF image decodes like the file it was
// made from, a PNG it writes reads back exactly, and what it cannot decode is an ImageError.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>

#include "images/images.h"
#include "passes/scene/scene.h"
#include "tests/unit/gltf_reference.h"
#include "tests/unit/scratch_folder.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const fs::path kBox = fs::path(NIGHTCAP_SHARED_DATA) / "gltf/BoxTextured/glTF";

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0);
    out += digits[n >> 18 & 63];
    out += digits[n >> 12 & 63];
    out += i + 1 < bytes.size() ? digits[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? digits[n & 63] : '=';
  }
  return out;
}

TEST(Images, FileAndMemoryDecodeAsOpenImageIOReads) {
  const fs::path png = kBox / "CesiumLogoFlat.png";
  const test::RefImage reference = test::read_image(png);
  const Rgba8Image from_file = decode_image_file(png, 16384);
  EXPECT_EQ(from_file.width, uint32_t(reference.width));
  EXPECT_EQ(from_file.height, uint32_t(reference.height));
  EXPECT_EQ(from_file.pixels, reference.rgba);
  const std::vector<uint8_t> bytes = test::read_bytes(png);
  const Rgba8Image from_memory = decode_image_memory("embedded.png", bytes, 16384);
  EXPECT_EQ(from_memory.width, from_file.width);
  EXPECT_EQ(from_memory.pixels, from_file.pixels);
}

TEST(Images, GreyAndGreyAlphaBecomeRgba) {
  const ScratchFolder scratch("images-test");
  for (int channels : {1, 2}) {
    const fs::path file = scratch.path / ("grey" + std::to_string(channels) + ".png");
    // Opaque, or transparent black: OpenImageIO premultiplies what it reads, and these read the
    // same either way.
    const std::vector<uint8_t> texels =
        channels == 1 ? std::vector<uint8_t>{10, 200, 30} : std::vector<uint8_t>{10, 255, 0, 0, 250, 255};
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), OIIO::ImageSpec(3, 1, channels, OIIO::TypeDesc::UINT8)) &&
                out->write_image(OIIO::TypeDesc::UINT8, texels.data()) && out->close());
    const Rgba8Image image = decode_image_file(file, 16384);
    const std::vector<uint8_t> expected =
        channels == 1 ? std::vector<uint8_t>{10, 10, 10, 255, 200, 200, 200, 255, 30, 30, 30, 255}
                      : std::vector<uint8_t>{10, 10, 10, 255, 0, 0, 0, 0, 250, 250, 250, 255};
    EXPECT_EQ(image.pixels, expected) << channels << " channel(s)";
  }
}

TEST(Images, AWrittenPngReadsBackExactly) {
  const ScratchFolder scratch("images-test");
  const fs::path file = scratch.path / "out.png";
  // Opaque, as final frames are: OpenImageIO premultiplies alpha on reading.
  std::vector<uint8_t> rgba(5 * 3 * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = i % 4 == 3 ? 255 : uint8_t(i * 37 + 11);
  write_png(file, rgba, 5, 3);
  const test::RefImage read = test::read_image(file);
  EXPECT_EQ(read.width, 5);
  EXPECT_EQ(read.height, 3);
  EXPECT_EQ(read.rgba, rgba);
}

TEST(Images, WhatCannotBeDecodedOrWrittenIsAnImageError) {
  const std::vector<uint8_t> garbage(100, 0x5a);
  EXPECT_THROW(decode_image_memory("embedded.png", garbage, 16384), ImageError);
  EXPECT_THROW(decode_image_file(kBox / "BoxTextured0.bin", 16384), ImageError);
  try {
    decode_image_file(kBox / "CesiumLogoFlat.png", 100);
    ADD_FAILURE() << "a 256x256 image was accepted with a 100-texel limit";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("256x256"), std::string::npos) << e.what();
  }
  const std::vector<uint8_t> pixel(4, 0);
  EXPECT_THROW(write_png("/nonexistent/folder/out.png", pixel, 1, 1), ImageError);
}

// tinygltf hands images in data URIs to the loader's callback, which decodes them in memory.
TEST(Images, AnEmbeddedGltfImageDecodesLikeItsFile) {
  const ScratchFolder scratch("images-test");
  const fs::path& dir = scratch.path;
  fs::copy_file(kBox / "BoxTextured0.bin", dir / "BoxTextured0.bin");
  nlohmann::json gltf = nlohmann::json::parse(std::ifstream(kBox / "BoxTextured.gltf"));
  gltf["images"][0]["uri"] = "data:image/png;base64," + base64(test::read_bytes(kBox / "CesiumLogoFlat.png"));
  std::ofstream(dir / "embedded.gltf") << gltf.dump();
  const Scene from_file = load_gltf((kBox / "BoxTextured.gltf").string());
  const Scene embedded = load_gltf((dir / "embedded.gltf").string());
  ASSERT_EQ(from_file.textures.size(), 1u);
  ASSERT_EQ(embedded.textures.size(), 1u);
  EXPECT_EQ(embedded.textures[0].width, from_file.textures[0].width);
  EXPECT_EQ(embedded.textures[0].height, from_file.textures[0].height);
  EXPECT_EQ(embedded.textures[0].rgba8, from_file.textures[0].rgba8);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
