// Small pictures of a frame's image resources for the report, drawn by the debugger's
// visualisations (inspect/visualise.h) and shrunk, one file per distinct content.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "captures/capture.h"
#include "images/images.h"
#include "inspect/visualise.h"

namespace nightcap {

// The pictures of one image: mip 0 of its one layer, of each layer of an array shown (the first
// kMaxLayersShown; of a probe array, both layers of each slot that holds a capture), or of
// kMaxLayersShown slices of a 3D image spread through its depth (of a kind whose cells span
// blocks of slices, through the first block), those at half the side so that four make a row.
struct Thumbnail {
  struct Picture {
    std::string file;  // relative to the report folder
    uint32_t layer = 0, slice = 0, width = 0, height = 0;
  };
  std::vector<Picture> pictures;
  // Of kinds drawn as distances (depth, shadow maps): the range every picture is drawn between.
  std::optional<DistanceRange> distances;
};

// A shadow atlas holds dozens of layers, one per light or view, and a row of them all would be
// the longest thing on a page of sixty passes: the first eight (two rows of four, all of a
// cascade set) show what they hold, and `inspect export --layer` shows any other.
inline constexpr uint32_t kMaxLayersShown = 8;

// The slices a 3D image's pictures are spread through: its depth, or of a kind whose cells span
// blocks of slices, a block's.
uint32_t shown_depth(const ResourceRecord& record);

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
  // Draws every image added (mip 0 of each layer shown; the depth of a depth-stencil image) into
  // `folder`/images/, a worker per core, distances of all its layers on one scale. Throws what
  // loading a blob throws (CaptureError).
  void write(const Capture& capture, const FrameRecord& frame, const std::filesystem::path& folder);
  // The thumbnail of `record`, or null for buffers and images never added.
  const Thumbnail* find(const ResourceRecord& record) const;

 private:
  // Hash, format, kind and shape: equal bytes are drawn otherwise in another shape (a cleared
  // 512² map of 16 layers and a 1024² one of 4).
  using Key = std::tuple<std::string, int, std::string_view, uint32_t, uint32_t, uint32_t, uint32_t, uint32_t>;
  static Key key_of(const ResourceRecord& record);
  uint32_t max_side_;
  std::vector<const ResourceRecord*> pending_;
  std::map<Key, Thumbnail> thumbnails_;
};

}  // namespace nightcap
