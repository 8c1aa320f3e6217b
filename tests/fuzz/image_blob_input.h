// The input of the image blob harness: six bytes saying what the manifest expects — format (an
// index into every format), width, height, mips, layers, depth — then the blob's bytes. Shared
// with the regression test that replays the inputs that once crashed the harness.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <optional>
#include <span>

#include "passes/core/format.h"

namespace nightcap::fuzz {

struct ImageBlobInput {
  FormatInfo format;
  ImageExtent extent;
  std::span<const uint8_t> blob;
};

// nullopt for an input too short, or for a chain longer than the image allows (the manifest
// refuses that before any blob is read).
inline std::optional<ImageBlobInput> parse_image_blob_input(std::span<const uint8_t> data) {
  constexpr size_t kHeader = 6;
  if (data.size() < kHeader) return std::nullopt;
  const auto& formats = all_formats();
  ImageBlobInput input{formats[data[0] % formats.size()], {}, data.subspan(kHeader)};
  input.extent.width = 1 + data[1] % 64;
  input.extent.height = 1 + data[2] % 64;
  input.extent.mips = 1 + data[3] % 7;
  input.extent.layers = 1 + data[4] % 6;
  input.extent.depth = 1 + data[5] % 4;  // the manifest allows a depth with layers too
  const uint32_t largest = std::max({input.extent.width, input.extent.height, input.extent.depth});
  if (input.extent.mips > uint32_t(std::bit_width(largest))) return std::nullopt;
  return input;
}

}  // namespace nightcap::fuzz
