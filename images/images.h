// Image decoding and PNG writing for nightcap_core, done by the image module (see
// image_module_abi.h), which is loaded on first use so that commands that touch no image never
// load OpenImageIO.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace nightcap {

// An image that cannot be decoded or written, or a module that cannot be loaded: the message
// says which.
struct ImageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Rgba8Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width * height * 4
};

// Any format OpenImageIO reads, any channel count: grey fills RGB, missing alpha is opaque.
Rgba8Image decode_image_file(const std::filesystem::path& file, uint32_t max_side);
// Encoded bytes in memory; `name`'s extension (".png", ".jpg") picks the format.
Rgba8Image decode_image_memory(const std::string& name, std::span<const uint8_t> bytes, uint32_t max_side);

void write_png(const std::filesystem::path& file, std::span<const uint8_t> rgba8, uint32_t width, uint32_t height);

}  // namespace nightcap
