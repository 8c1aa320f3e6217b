// Capture blobs: every format, extent and compression round-trips bit-exactly (NaN payloads,
// -0, denormals and packed words included); mismatched, truncated or damaged files fail with a
// CaptureError naming the file, except damaged pixel data, which comes back at the right size
// for the capture's content hash to catch. Nothing crashes.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <half.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include "captures/blob_codec.h"
#include "captures/codec_choice.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

class BlobDir {
 public:
  BlobDir() {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    std::string name =
        std::string("nightcap-blob-") + test->test_suite_name() + "-" + test->name() + "-" + std::to_string(getpid());
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = fs::temp_directory_path() / name;
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~BlobDir() { fs::remove_all(path_); }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::vector<uint8_t> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, std::span<const uint8_t> bytes) {
  // Removing first: overwriting with O_TRUNC makes ext4 flush the old blocks (auto_da_alloc),
  // which turns thousands of small rewrites into a minute of waiting.
  fs::remove(file);
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Random codes, with the float values most likely to be mangled by a conversion placed first.
std::vector<uint8_t> random_raw(const FormatInfo& format, const ImageExtent& extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> raw(raw_image_bytes(format, extent));
  for (uint8_t& b : raw) b = uint8_t(rng());
  const uint64_t depth_plane = raw_subresource_offset(format, extent, 1, 0, 0);
  if (format.encoding == ChannelEncoding::sfloat16) {
    const uint16_t specials[] = {0x7c00, 0xfc00, 0x8000, 0x0000, 0x0001, 0x83ff, 0x7e01, 0xfd55, 0x7bff, 0x7fff};
    std::memcpy(raw.data(), specials, std::min(sizeof specials, raw.size()));
  } else if (format.encoding == ChannelEncoding::sfloat32 || format.encoding == ChannelEncoding::depth32_stencil8) {
    const uint32_t specials[] = {0x7f800001, 0xffc00000, 0x7fbfffff, 0x7f800000, 0xff800000,
                                 0x80000000, 0x00000001, 0x807fffff, 0x00400000, 0x7fc12345};
    std::memcpy(raw.data(), specials, std::min(sizeof specials, size_t(depth_plane)));
  }
  return raw;
}

// Gently varying codes that ZIP actually compresses (random ones it stores as they are): each
// byte a slow ramp along the row with a little noise.
std::vector<uint8_t> smooth_raw(const FormatInfo& format, const ImageExtent& extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> raw(raw_image_bytes(format, extent));
  const size_t row = size_t(extent.width) * format.texel_bytes;
  for (size_t i = 0; i < raw.size(); ++i) {
    const size_t x = i % row;
    // High bytes of a 16- or 32-bit value stay still; low ones follow the ramp.
    raw[i] = uint8_t(i % 2 ? 0x3c : x / 16 + rng() % 3);
  }
  return raw;
}

// PXR24 included: it is lossless on HALF and UINT samples and falls back to ZIP for FLOAT ones.
const ImageEncoding kEncodings[] = {{ExrCompression::none},    {ExrCompression::rle},    {ExrCompression::zips, 1},
                                    {ExrCompression::zip, 1},  {ExrCompression::zip, 9}, {ExrCompression::piz},
                                    {ExrCompression::pxr24, 4}};

class ImageRoundTrip : public testing::TestWithParam<FormatInfo> {};

TEST_P(ImageRoundTrip, BitExactForEveryExtentAndCompression) {
  const FormatInfo& format = GetParam();
  std::vector<ImageExtent> extents = {{7, 5, 1, 3, 2}, {1, 1, 1, 1, 1}, {64, 33, 1, 7, 1}};
  // Depth formats are never 3D images.
  if (!format.is_depth) extents.insert(extents.end(), {{13, 1, 4, 1, 1}, {16, 9, 4, 3, 1}});
  BlobDir dir;
  uint32_t seed = 1;
  for (const ImageExtent& extent : extents)
    for (ImageEncoding encoding : kEncodings) {
      SCOPED_TRACE(std::to_string(extent.width) + "x" + std::to_string(extent.height) + "x" +
                   std::to_string(extent.depth) + " mips " + std::to_string(extent.mips) + " layers " +
                   std::to_string(extent.layers) + " " + image_encoding_name(encoding));
      const std::vector<uint8_t> raw = random_raw(format, extent, seed++);
      const fs::path file = dir / ("blob." + image_blob_extension());
      write_image_blob(file, format, extent, raw, encoding);
      const std::vector<uint8_t> back = read_image_blob(file, format, extent);
      ASSERT_EQ(back.size(), raw.size());
      EXPECT_TRUE(back == raw);
    }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, ImageRoundTrip, testing::ValuesIn(all_formats()),
                         [](const testing::TestParamInfo<FormatInfo>& info) { return std::string(info.param.name); });

TEST(ImageBlob, CompressedZipChunksRoundTrip) {
  // ZIP chunks are inflated by libdeflate, split among threads for a large part: 45 rows are two
  // whole 16-row chunks and a partial one, the 1-row ZIPS chunks 45.
  BlobDir dir;
  const ImageExtent extent{1280, 45, 1, 2, 1};
  for (VkFormat vk : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_R32_SFLOAT})
    for (ImageEncoding encoding : {ImageEncoding{ExrCompression::zip, 1}, ImageEncoding{ExrCompression::zip, 9},
                                   ImageEncoding{ExrCompression::zips, 4}}) {
      const FormatInfo format = *format_info(vk);
      SCOPED_TRACE(std::string(format.name) + " " + image_encoding_name(encoding));
      const std::vector<uint8_t> raw = smooth_raw(format, extent, 3);
      const fs::path file = dir / "smooth.exr";
      write_image_blob(file, format, extent, raw, encoding);
      // Compressed, or the inflating was not what ran.
      EXPECT_LT(fs::file_size(file), raw.size() / 2);
      EXPECT_TRUE(read_image_blob(file, format, extent) == raw);
    }
}

TEST(ImageBlob, OtherToolsSeeTheCodesAndTheFormat) {
  // A tool that opens the EXR must see integer codes, not normalised or reinterpreted values.
  BlobDir dir;
  const FormatInfo format = *format_info(VK_FORMAT_R16G16_UNORM);
  const ImageExtent extent{2, 1, 1, 1, 2};
  const std::vector<uint8_t> raw = {0x34, 0x12, 0xff, 0xff, 0x01, 0x00, 0x00, 0x80, 0, 0, 0, 0, 0, 0, 0, 0};
  const fs::path file = dir / "codes.exr";
  write_image_blob(file, format, extent, raw, {ExrCompression::zip});
  Imf::MultiPartInputFile in(file.c_str());
  ASSERT_EQ(in.parts(), 2);
  EXPECT_EQ(in.header(1).name(), "a0.m0.l1");
  const auto* name = in.header(0).findTypedAttribute<Imf::StringAttribute>("nightcap.format");
  ASSERT_TRUE(name);
  EXPECT_EQ(name->value(), "R16G16_UNORM");
  uint32_t rg[2][2];
  Imf::FrameBuffer frame_buffer;
  frame_buffer.insert("R", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(&rg[0][0]), 8, 16));
  frame_buffer.insert("G", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(&rg[0][1]), 8, 16));
  Imf::InputPart part(in, 0);
  part.setFrameBuffer(frame_buffer);
  part.readPixels(0, 0);
  EXPECT_EQ(rg[0][0], 0x1234u);
  EXPECT_EQ(rg[0][1], 0xffffu);
  EXPECT_EQ(rg[1][0], 1u);
  EXPECT_EQ(rg[1][1], 0x8000u);
}

TEST(ImageBlob, EightBitCodesAreHalfSamplesHoldingTheInteger) {
  BlobDir dir;
  const FormatInfo format = *format_info(VK_FORMAT_R8G8_UNORM);
  const std::vector<uint8_t> raw = {0, 255, 1, 128};
  const fs::path file = dir / "codes8.exr";
  write_image_blob(file, format, {2, 1}, raw, {ExrCompression::piz});
  half rg[2][2];
  {
    Imf::MultiPartInputFile in(file.c_str());
    Imf::FrameBuffer frame_buffer;
    frame_buffer.insert("R", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&rg[0][0]), 4, 8));
    frame_buffer.insert("G", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&rg[0][1]), 4, 8));
    Imf::InputPart part(in, 0);
    part.setFrameBuffer(frame_buffer);
    part.readPixels(0, 0);
  }
  EXPECT_EQ(float(rg[0][0]), 0.0f);
  EXPECT_EQ(float(rg[0][1]), 255.0f);
  EXPECT_EQ(float(rg[1][0]), 1.0f);
  EXPECT_EQ(float(rg[1][1]), 128.0f);

  // A sample that is no 8-bit integer (here 0.5) is damage, not a code.
  Imf::Header header(2, 1);
  header.setName("a0.m0.l0");
  header.setType(Imf::SCANLINEIMAGE);
  header.channels().insert("R", Imf::Channel(Imf::HALF));
  header.channels().insert("G", Imf::Channel(Imf::HALF));
  header.insert("nightcap.format", Imf::StringAttribute("R8G8_UNORM"));
  for (const char* name : {"nightcap.width", "nightcap.height", "nightcap.depth", "nightcap.mips", "nightcap.layers"})
    header.insert(name, Imf::IntAttribute(std::string(name) == "nightcap.width" ? 2 : 1));
  rg[1][1] = 0.5f;
  {
    Imf::MultiPartOutputFile out(file.c_str(), &header, 1);
    Imf::FrameBuffer frame_buffer;
    frame_buffer.insert("R", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&rg[0][0]), 4, 8));
    frame_buffer.insert("G", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&rg[0][1]), 4, 8));
    Imf::OutputPart part(out, 0);
    part.setFrameBuffer(frame_buffer);
    part.writePixels(1);
  }
  try {
    read_image_blob(file, format, {2, 1});
    FAIL() << "a non-integer sample was read as a code";
  } catch (const CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find("no code of R8G8_UNORM"), std::string::npos) << e.what();
  }
}

TEST(ImageBlob, DepthStencilAspectsAreSeparateParts) {
  BlobDir dir;
  const FormatInfo format = *format_info(VK_FORMAT_D32_SFLOAT_S8_UINT);
  const ImageExtent extent{3, 2, 1, 2, 1};
  const std::vector<uint8_t> raw = random_raw(format, extent, 7);
  write_image_blob(dir / "ds.exr", format, extent, raw, {ExrCompression::piz});
  EXPECT_EQ(read_image_blob(dir / "ds.exr", format, extent), raw);
  // Four parts (2 aspects x 2 mips): the same file read as D32_SFLOAT has the wrong part count.
  EXPECT_THROW(read_image_blob(dir / "ds.exr", *format_info(VK_FORMAT_D32_SFLOAT), extent), CaptureError);
}

void expect_capture_error(const std::function<void()>& read, const fs::path& file, const std::string& what = "") {
  try {
    read();
    ADD_FAILURE() << "no CaptureError for " << file << " (" << what << ")";
  } catch (const CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(ImageBlob, MismatchedFormatOrExtentIsRejected) {
  BlobDir dir;
  const FormatInfo rgba16f = *format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  const ImageExtent extent{7, 5, 1, 3, 2};
  const fs::path file = dir / "image.exr";
  write_image_blob(file, rgba16f, extent, random_raw(rgba16f, extent, 3), {ExrCompression::zip});
  const auto read_as = [&](VkFormat format, ImageExtent e) {
    expect_capture_error([&] { read_image_blob(file, *format_info(format), e); }, file);
  };
  read_as(VK_FORMAT_R32G32B32A32_SFLOAT, extent);  // same channels, other type
  read_as(VK_FORMAT_R32G32_SFLOAT, extent);        // same texel size
  read_as(VK_FORMAT_R16G16_SFLOAT, extent);
  read_as(VK_FORMAT_R32G32B32A32_UINT, extent);
  read_as(VK_FORMAT_R16G16B16A16_SFLOAT, {8, 5, 1, 3, 2});
  read_as(VK_FORMAT_R16G16B16A16_SFLOAT, {7, 6, 1, 3, 2});
  read_as(VK_FORMAT_R16G16B16A16_SFLOAT, {7, 5, 1, 2, 2});
  read_as(VK_FORMAT_R16G16B16A16_SFLOAT, {7, 5, 1, 3, 1});
  read_as(VK_FORMAT_R16G16B16A16_SFLOAT, {7, 1, 5, 3, 2});  // same rows per part, not 3D

  // Packed formats share one UINT channel; only the recorded format tells them apart.
  const FormatInfo a2b10 = *format_info(VK_FORMAT_A2B10G10R10_UNORM_PACK32);
  write_image_blob(file, a2b10, {4, 4}, random_raw(a2b10, {4, 4}, 4), {ExrCompression::rle});
  read_as(VK_FORMAT_B10G11R11_UFLOAT_PACK32, {4, 4});
  read_as(VK_FORMAT_R32_UINT, {4, 4});

  // A 16-bit code cannot be read back as an 8-bit one, though both are UINT channels.
  const FormatInfo r16 = *format_info(VK_FORMAT_R16_UINT);
  write_image_blob(file, r16, {4, 4}, random_raw(r16, {4, 4}, 5), {ExrCompression::none});
  read_as(VK_FORMAT_R8_UINT, {4, 4});
}

TEST(ImageBlob, MissingOrForeignFileIsRejected) {
  BlobDir dir;
  const FormatInfo format = *format_info(VK_FORMAT_R8G8B8A8_UNORM);
  const fs::path missing = dir / "missing.exr";
  expect_capture_error([&] { read_image_blob(missing, format, {4, 4}); }, missing);
  const fs::path buffer = dir / "buffer.exr";
  write_buffer_blob(buffer, std::vector<uint8_t>(100, 1), 3);
  expect_capture_error([&] { read_image_blob(buffer, format, {4, 4}); }, buffer);
}

// Truncated copies and copies with one damaged byte must either fail with a CaptureError
// naming the file or return data of the expected size (damaged pixel data is only caught by
// the capture's content hash); a crash fails the suite. Every prefix of the headers is tried
// and a sample of the longer ones; every byte is damaged once, by a full or a one-bit flip.
void damage(const fs::path& file, const std::function<std::vector<uint8_t>()>& read, size_t expected_size) {
  const std::vector<uint8_t> good = file_bytes(file);
  size_t errors = 0, returned = 0;
  const auto expect_capture_error_or_data = [&](const std::string& what, bool data_allowed) {
    try {
      const size_t size = read().size();
      EXPECT_TRUE(data_allowed) << what << " was accepted";
      EXPECT_EQ(size, expected_size) << what;
      ++returned;
    } catch (const CaptureError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << what << ": " << e.what();
      ++errors;
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not a CaptureError: " << e.what();
    }
  };
  for (size_t length = 0; length < good.size(); length += length < 1024 ? 1 : 7) {
    write_bytes(file, std::span(good).first(length));
    expect_capture_error_or_data("truncated to " + std::to_string(length), false);
  }
  std::mt19937 rng(11);
  for (size_t at = 0; at < good.size(); ++at) {
    std::vector<uint8_t> bad = good;
    const uint8_t mask = at % 2 ? 0xff : uint8_t(1u << rng() % 8);
    bad[at] ^= mask;
    write_bytes(file, bad);
    expect_capture_error_or_data("byte " + std::to_string(at) + " ^ " + std::to_string(mask), true);
  }
  // Both outcomes must occur, or the damage did not reach both the headers and the data.
  EXPECT_GT(errors, 0u);
  EXPECT_GT(returned, 0u);
}

TEST(ImageBlob, TruncatedOrFlippedFilesFailCleanly) {
  BlobDir dir;
  struct Case {
    VkFormat format;
    ImageExtent extent;
    ImageEncoding encoding;
    bool smooth = false;  // content ZIP compresses, so that damage reaches an inflated chunk
  };
  const Case cases[] = {
      {VK_FORMAT_R16G16B16A16_SFLOAT, {7, 5, 1, 2, 2}, {ExrCompression::zip}},
      {VK_FORMAT_R16G16B16A16_SFLOAT, {40, 17, 1, 1, 1}, {ExrCompression::zip}, true},
      {VK_FORMAT_D32_SFLOAT_S8_UINT, {6, 5, 1, 2, 1}, {ExrCompression::piz}},
      {VK_FORMAT_R8G8B8A8_UNORM, {9, 4, 1, 2, 1}, {ExrCompression::none}},
      {VK_FORMAT_A2B10G10R10_UNORM_PACK32, {5, 2, 3, 1, 1}, {ExrCompression::rle}},
  };
  for (const Case& c : cases) {
    const FormatInfo format = *format_info(c.format);
    SCOPED_TRACE(std::string(format.name) + " " + image_encoding_name(c.encoding) + (c.smooth ? " smooth" : ""));
    const fs::path file = dir / (std::string(format.name) + (c.smooth ? "-smooth" : "") + ".exr");
    write_image_blob(file, format, c.extent,
                     c.smooth ? smooth_raw(format, c.extent, 9) : random_raw(format, c.extent, 9), c.encoding);
    damage(
        file, [&] { return read_image_blob(file, format, c.extent); }, raw_image_bytes(format, c.extent));
  }
}

TEST(BufferBlob, RoundTripsAtEverySize) {
  BlobDir dir;
  std::mt19937 rng(5);
  for (size_t size : {size_t(0), size_t(1), size_t(1000), size_t(1) << 20})
    for (int level : {-1, 1, 3, 9}) {
      SCOPED_TRACE(std::to_string(size) + " bytes at level " + std::to_string(level));
      std::vector<uint8_t> raw(size);
      // Half random, half repetitive, so compression has something to do.
      for (size_t i = 0; i < size; ++i) raw[i] = i < size / 2 ? uint8_t(rng()) : uint8_t(i / 64);
      const fs::path file = dir / ("buffer." + buffer_blob_extension());
      write_buffer_blob(file, raw, level);
      EXPECT_EQ(read_buffer_blob(file, size), raw);
    }
}

TEST(BufferBlob, WrongSizeOrDamageIsRejected) {
  BlobDir dir;
  const fs::path file = dir / "buffer.bin.zst";
  std::vector<uint8_t> raw(3000);
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = uint8_t(i * 7 / 5);
  write_buffer_blob(file, raw, 3);
  expect_capture_error([&] { read_buffer_blob(file, raw.size() - 1); }, file, "smaller");
  expect_capture_error([&] { read_buffer_blob(file, raw.size() + 1); }, file, "larger");
  expect_capture_error([&] { read_buffer_blob(file, (uint64_t(4) << 30) + 1); }, file, "over 4 GiB");
  const fs::path missing = dir / "missing.bin.zst";
  expect_capture_error([&] { read_buffer_blob(missing, 0); }, missing, "missing");

  std::vector<uint8_t> twice = file_bytes(file);
  const std::vector<uint8_t> frame = twice;
  twice.insert(twice.end(), frame.begin(), frame.end());
  write_bytes(file, twice);
  expect_capture_error([&] { read_buffer_blob(file, raw.size()); }, file, "two frames");
  std::vector<uint8_t> trailing = frame;
  trailing.push_back(0);
  write_bytes(file, trailing);
  expect_capture_error([&] { read_buffer_blob(file, raw.size()); }, file, "trailing byte");

  write_bytes(file, frame);
  damage(
      file, [&] { return read_buffer_blob(file, raw.size()); }, raw.size());
}

TEST(CodecChoice, EveryKindTakesZipAtLevelOne) {
  // nightcap's libdeflate ZIP writer is faster than PIZ on every kind, and as small or smaller
  // over a frame (captures/codec_choice.cpp): every kind the renderer registers keeps the default.
  for (const ResourceKind kind : registered_kinds()) {
    if (kind.name().starts_with("test_")) continue;  // registered by tests
    for (const VkFormat format : {VK_FORMAT_R8_UINT, VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_D32_SFLOAT}) {
      const ImageEncoding encoding = image_encoding_for(kind, *format_info(format));
      EXPECT_EQ(encoding.compression, ExrCompression::zip) << kind.name();
      EXPECT_EQ(encoding.zip_level, 1) << kind.name();
    }
  }
}

TEST(CodecChoice, AKindsRegisteredCompressionChoosesTheCodec) {
  static const KindRegistration wavelet(
      {.kind = ResourceKind("test_wavelet_table"), .compression = {KindCompression::Method::wavelet, 1}});
  const ImageEncoding encoding =
      image_encoding_for(ResourceKind("test_wavelet_table"), *format_info(VK_FORMAT_R16G16_SFLOAT));
  EXPECT_EQ(encoding.compression, ExrCompression::piz);
}

TEST(DecodedParts, ASharedPartIsDecodedOnceAndDamageIsNotHidden) {
  // Two records of a mip chain that differ only in mip 1, as after two passes of a bloom chain:
  // reading the second through the cache copies mip 0 instead of decoding it again.
  BlobDir dir;
  const FormatInfo format = *format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  const ImageExtent extent{512, 128, 1, 3, 1};  // mip 0: 512 KiB, a shared part; mips 1, 2 too small
  std::vector<uint8_t> first = smooth_raw(format, extent, 1), second = first;
  const uint64_t mip1 = raw_subresource_offset(format, extent, 0, 1, 0);
  for (uint64_t i = mip1; i < mip1 + 4096; ++i) second[i] ^= 0x11;
  for (const ImageEncoding encoding : {ImageEncoding{ExrCompression::zip, 1}, ImageEncoding{ExrCompression::piz}}) {
    SCOPED_TRACE(image_encoding_name(encoding));
    write_image_blob(dir / "first.exr", format, extent, first, encoding);
    write_image_blob(dir / "second.exr", format, extent, second, encoding);
    DecodedParts parts(64u << 20);
    EXPECT_EQ(read_image_blob(dir / "first.exr", format, extent, -1, &parts), first);
    EXPECT_EQ(parts.hits(), 0u);
    EXPECT_EQ(read_image_blob(dir / "second.exr", format, extent, -1, &parts), second);
    EXPECT_EQ(parts.hits(), 1u);
    EXPECT_EQ(read_image_blob(dir / "first.exr", format, extent, -1, &parts), first);
    EXPECT_EQ(parts.hits(), 2u);

    // A flipped byte in the second file's mip 0 changes its digest: decoded, not found, it
    // fails as damage (or decodes to other bytes, which the capture's hash check refuses).
    std::vector<uint8_t> bytes = file_bytes(dir / "second.exr");
    bytes[bytes.size() / 4] ^= 0x40;
    write_bytes(dir / "damaged.exr", bytes);
    try {
      EXPECT_NE(read_image_blob(dir / "damaged.exr", format, extent, -1, &parts), second);
    } catch (const CaptureError&) {
    }
    EXPECT_EQ(parts.hits(), 2u);
  }
}

TEST(DecodedParts, KeepsNoMoreThanItsBudgetOldestDroppedFirst) {
  DecodedParts parts(10);
  const std::vector<uint8_t> six(6, 1), four(4, 2), five(5, 3);
  parts.keep({1, 1}, six);
  parts.keep({2, 2}, four);
  ASSERT_TRUE(parts.find({1, 1}));
  EXPECT_EQ(*parts.find({2, 2}), four);
  parts.keep({3, 3}, five);  // 15 bytes: the oldest goes
  EXPECT_FALSE(parts.find({1, 1}));
  EXPECT_TRUE(parts.find({2, 2}));
  EXPECT_TRUE(parts.find({3, 3}));
  parts.keep({4, 4}, std::vector<uint8_t>(11));  // larger than the budget: not kept
  EXPECT_FALSE(parts.find({4, 4}));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
