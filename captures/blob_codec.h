// Encoding of resource contents into capture blobs, and back, bit-exactly.
// Images become OpenEXR (multi-part: one part per aspect, mip and layer) whose channels keep
// the raw codes: HALF and FLOAT keep their bits, UNORM/UINT/sRGB bytes and packed 32-bit
// words are stored as EXR UINT channels. Buffers become zstd frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "passes/core/format.h"

namespace nightcap {

// A capture that cannot be read: the message names the file and the problem.
struct CaptureError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ExrCompression { none, rle, zip, piz };

// File extension of blobs: "exr" for images, "bin.zst" for buffers.
std::string image_blob_extension();
std::string buffer_blob_extension();

// `raw` is in the raw image layout of format.h.
void write_image_blob(const std::filesystem::path& file, const FormatInfo& format, const ImageExtent& extent,
                      std::span<const uint8_t> raw, ExrCompression compression);
// Throws CaptureError (naming `file`) when the file is unreadable, truncated, or its parts
// do not match the format and extent.
std::vector<uint8_t> read_image_blob(const std::filesystem::path& file, const FormatInfo& format,
                                     const ImageExtent& extent);

void write_buffer_blob(const std::filesystem::path& file, std::span<const uint8_t> raw, int zstd_level);
std::vector<uint8_t> read_buffer_blob(const std::filesystem::path& file, uint64_t expected_size);

}  // namespace nightcap
