// Encoding of resource contents into capture blobs, and back, bit-exactly.
// Images become OpenEXR (multi-part: one part per aspect, mip and layer) whose channels keep
// the raw codes: HALF and FLOAT keep their bits; 8-bit codes are HALF samples holding the
// integer code (HALF is exact up to 2048, and half the bytes of a UINT sample to compress);
// 16-bit codes and packed 32-bit words are EXR UINT channels. Buffers become zstd frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "captures/decoded_parts.h"
#include "passes/core/format.h"

namespace nightcap {

// A capture that cannot be read: the message names the file and the problem.
struct CaptureError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// OpenEXR's lossless codecs. pxr24 is lossless on HALF and UINT channels only, so an image
// with FLOAT channels written with it is stored with zip instead.
enum class ExrCompression { none, rle, zips, zip, piz, pxr24 };

struct ImageEncoding {
  ExrCompression compression = ExrCompression::zip;
  int zip_level = 4;  // zlib level of zip, zips and pxr24 (1 fastest … 9 smallest)
};

// "zip1" … "zip9", "zips1" …, "pxr24_1" …: a codec with a zlib level; "zip": level 4.
std::string image_encoding_name(ImageEncoding encoding);
std::optional<ImageEncoding> image_encoding_by_name(std::string_view name);

// File extension of blobs: "exr" for images, "bin.zst" for buffers.
std::string image_blob_extension();
std::string buffer_blob_extension();

// `raw` is in the raw image layout of format.h. `threads`: OpenEXR threads compressing this
// file (0: the calling thread alone; -1: OpenEXR's pool when the image is large).
void write_image_blob(const std::filesystem::path& file, const FormatInfo& format, const ImageExtent& extent,
                      std::span<const uint8_t> raw, ImageEncoding encoding, int threads = -1);
// Throws CaptureError (naming `file`) when the file is unreadable, truncated, or its parts
// do not match the format and extent. `threads`: OpenEXR threads decoding this file, as for
// write_image_blob (0 for a caller that already keeps every core busy).
// `decoded_parts`: where parts of this blob that other blobs share are found, and kept.
std::vector<uint8_t> read_image_blob(const std::filesystem::path& file, const FormatInfo& format,
                                     const ImageExtent& extent, int threads = -1,
                                     DecodedParts* decoded_parts = nullptr);
// The smallest part that read_image_blob looks for in, and keeps in, DecodedParts.
constexpr uint64_t kSharedPartBytes = 256u << 10;

void write_buffer_blob(const std::filesystem::path& file, std::span<const uint8_t> raw, int zstd_level);
std::vector<uint8_t> read_buffer_blob(const std::filesystem::path& file, uint64_t expected_size);

}  // namespace nightcap
