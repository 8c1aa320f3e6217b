// Small pictures of a frame's image resources for the report, drawn by the debugger's
// visualisations (inspect/visualise.h) and shrunk, one file per distinct content.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "captures/capture.h"
#include "images/images.h"

namespace nightcap {

struct Thumbnail {
  std::string file;  // relative to the report folder
  uint32_t width = 0, height = 0;
};

// An RGBA8 picture shrunk to fit `max_side` by averaging the source pixels each target pixel
// covers. `srgb`: the codes are sRGB-encoded light, averaged as linear light and encoded again
// (averaging the codes would darken edges).
Rgba8Image shrink(const Rgba8Image& picture, uint32_t max_side, bool srgb);

class ThumbnailSet {
 public:
  explicit ThumbnailSet(uint32_t max_side) : max_side_(max_side) {}

  // An image to draw (buffers are ignored). Versions with the same content, format and kind are
  // drawn once.
  void add(const ResourceRecord& record);
  // Draws every image added (mip 0, layer 0; the depth of a depth-stencil image) into
  // `folder`/images/, a worker per core. Throws what loading a blob throws (CaptureError).
  void write(const Capture& capture, const FrameRecord& frame, const std::filesystem::path& folder);
  // The thumbnail of `record`, or null for buffers and images never added.
  const Thumbnail* find(const ResourceRecord& record) const;

 private:
  using Key = std::tuple<std::string, int, std::string_view>;  // hash, format, kind
  static Key key_of(const ResourceRecord& record);
  uint32_t max_side_;
  std::vector<const ResourceRecord*> pending_;
  std::map<Key, Thumbnail> thumbnails_;
};

}  // namespace nightcap
