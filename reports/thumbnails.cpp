#include "reports/thumbnails.h"

#include <algorithm>
#include <cmath>

#include "compare/parallel.h"

namespace nightcap {

Rgba8Image shrink(const Rgba8Image& picture, uint32_t max_side, bool srgb) {
  const uint32_t w = picture.width, h = picture.height;
  if (w <= max_side && h <= max_side) return picture;
  const double scale = double(max_side) / std::max(w, h);
  Rgba8Image out;
  out.width = std::max(1u, uint32_t(std::lround(w * scale)));
  out.height = std::max(1u, uint32_t(std::lround(h * scale)));
  out.pixels.resize(size_t(out.width) * out.height * 4);
  std::array<float, 256> linear{};
  for (int code = 0; code < 256; ++code) linear[code] = srgb ? srgb_to_linear(code / 255.0f) : code / 255.0f;
  for (uint32_t y = 0; y < out.height; ++y) {
    const uint32_t y0 = uint32_t(uint64_t(y) * h / out.height),
                   y1 = std::max(y0 + 1, uint32_t(uint64_t(y + 1) * h / out.height));
    for (uint32_t x = 0; x < out.width; ++x) {
      const uint32_t x0 = uint32_t(uint64_t(x) * w / out.width),
                     x1 = std::max(x0 + 1, uint32_t(uint64_t(x + 1) * w / out.width));
      uint8_t* target = &out.pixels[(size_t(y) * out.width + x) * 4];
      double sum[4] = {0, 0, 0, 0};
      for (uint32_t sy = y0; sy < y1; ++sy)
        for (uint32_t sx = x0; sx < x1; ++sx) {
          const uint8_t* source = &picture.pixels[(size_t(sy) * w + sx) * 4];
          for (int c = 0; c < 3; ++c) sum[c] += linear[source[c]];
          sum[3] += source[3];
        }
      const double count = double(y1 - y0) * (x1 - x0);
      for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / count;
        target[c] = uint8_t(std::lround(std::clamp(srgb ? linear_to_srgb(float(mean)) : mean, 0.0, 1.0) * 255.0));
      }
      target[3] = uint8_t(std::lround(sum[3] / count));
    }
  }
  return out;
}

namespace {

// Drops the pictures of a probe array's slots whose two layers hold nothing but zeros (never
// captured), keeping the first slot's when every slot is empty.
void drop_empty_slots(const ResourceRecord& record, const std::vector<uint8_t>& raw, Thumbnail& thumbnail) {
  const FormatInfo f = *format_info(record.format);
  const uint64_t bytes = raw_subresource_bytes(f, record.extent, 0, 0);
  auto empty = [&](uint32_t layer) {
    const uint64_t offset = raw_subresource_offset(f, record.extent, 0, 0, layer);
    if (offset + bytes > raw.size()) return false;
    return std::all_of(raw.begin() + offset, raw.begin() + offset + bytes, [](uint8_t b) { return b == 0; });
  };
  std::vector<Thumbnail::Picture> kept;
  for (const Thumbnail::Picture& p : thumbnail.pictures)
    if (!empty(p.layer / 2 * 2) || !empty(p.layer / 2 * 2 + 1)) kept.push_back(p);
  if (kept.empty())
    kept.assign(thumbnail.pictures.begin(),
                thumbnail.pictures.begin() + std::min<size_t>(2, thumbnail.pictures.size()));
  thumbnail.pictures = std::move(kept);
}

}  // namespace

uint32_t shown_depth(const ResourceRecord& record) {
  const std::optional<SliceBlocks>& blocks = kind_info(record.kind).slice_blocks;
  return blocks ? record.extent.depth / blocks->blocks : record.extent.depth;
}

ThumbnailSet::Key ThumbnailSet::key_of(const ResourceRecord& record) {
  const ImageExtent& e = record.extent;
  return {record.hash, int(record.format), record.kind.name(), e.width, e.height, e.depth, e.mips, e.layers};
}

void ThumbnailSet::add(const ResourceRecord& record) {
  if (record.is_buffer || record.hash.empty()) return;
  const Key key = key_of(record);
  if (thumbnails_.count(key)) return;
  // Numbered files: a hash read from a manifest never becomes part of a path.
  const std::string name = "images/" + std::to_string(thumbnails_.size() + 1);
  Thumbnail& thumbnail = thumbnails_[key];
  // A probe array shows each slot's two hemispheres (those left empty are dropped in write()).
  const bool by_slot = kind_info(record.kind).layer_directions.has_value();
  const uint32_t layers = by_slot ? record.extent.layers : std::min(record.extent.layers, kMaxLayersShown);
  if (const uint32_t depth = shown_depth(record); depth > 1) {
    const uint32_t slices = std::min(depth, kMaxLayersShown);
    for (uint32_t k = 0; k < slices; ++k)
      thumbnail.pictures.push_back({name + "-" + std::to_string(k) + ".png", 0, k * depth / slices});
  } else {
    for (uint32_t layer = 0; layer < layers; ++layer)
      thumbnail.pictures.push_back({name + (layers > 1 ? "-" + std::to_string(layer) : "") + ".png", layer});
  }
  pending_.push_back(&record);
}

void ThumbnailSet::write(const Capture& capture, const FrameRecord& frame, const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder / "images");
  for_each_on_cores(pending_.size(), [&](size_t i) {
    const ResourceRecord& record = *pending_[i];
    Thumbnail& thumbnail = thumbnails_.at(key_of(record));
    const std::vector<uint8_t> raw = capture.load(record);
    if (kind_info(record.kind).layer_directions) drop_empty_slots(record, raw, thumbnail);
    for (const Thumbnail::Picture& picture : thumbnail.pictures) {
      const std::optional<DistanceRange> range = distance_range(record, raw, frame, {0, picture.layer, picture.slice});
      if (!range) continue;
      if (!thumbnail.distances)
        thumbnail.distances = range;
      else
        thumbnail.distances = DistanceRange{std::min(thumbnail.distances->nearest, range->nearest),
                                            std::max(thumbnail.distances->farthest, range->farthest)};
    }
    // Layers side by side at half the side, four to a row.
    const uint32_t side = thumbnail.pictures.size() > 1 ? max_side_ / 2 : max_side_;
    const bool light = kind_info(record.kind).light;
    for (Thumbnail::Picture& picture : thumbnail.pictures) {
      const Rgba8Image drawn = visualise(record, raw, frame, {0, picture.layer, picture.slice},
                                         VisualAspect::depth_or_colour, thumbnail.distances);
      const Rgba8Image small = shrink(drawn, side, light);
      write_png(folder / picture.file, small.pixels, small.width, small.height);
      picture.width = small.width;
      picture.height = small.height;
    }
  });
  pending_.clear();
}

const Thumbnail* ThumbnailSet::find(const ResourceRecord& record) const {
  const auto it = thumbnails_.find(key_of(record));
  return it == thumbnails_.end() || it->second.pictures.front().width == 0 ? nullptr : &it->second;
}

}  // namespace nightcap
