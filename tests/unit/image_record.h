// Images built in unit tests: their records, as a capture would hold them, and their bytes.
#pragma once

#include <cstring>
#include <string>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

inline ResourceRecord image_record(VkFormat format, ResourceKind kind, uint32_t width, uint32_t height,
                                   uint32_t mips = 1, std::string name = "image") {
  ResourceRecord r;
  r.resource = std::move(name);
  r.is_buffer = false;
  r.format = format;
  r.kind = kind;
  r.extent = {width, height, 1, mips, 1};
  return r;
}

// R32 channels in the raw layout: the floats' bytes.
inline std::vector<uint8_t> floats(const std::vector<float>& values) {
  std::vector<uint8_t> bytes(values.size() * 4);
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

}  // namespace nightcap
