#include "inspect/heatmap.h"

#include <algorithm>
#include <cmath>

#include "inspect/decode.h"

namespace nightcap {

ListHeatmap list_heatmap(const ResourceRecord& record, std::span<const uint8_t> raw, std::optional<uint32_t> slice) {
  const std::optional<TexelLists>& lists = kind_info(record.kind).lists;
  if (!lists)
    throw InspectError(record.resource +
                       " holds no lists: --heatmap draws an image whose texels index lists, such "
                       "as lights.clusters");
  const uint32_t slices = record.extent.depth;
  if (slice && *slice >= slices)
    throw InspectError(record.resource + " has " + std::to_string(slices) + " slices: no slice " +
                       std::to_string(*slice));
  const SubresourceReader reader(record, raw, 0, 0);
  ListHeatmap map;
  map.width = reader.width();
  map.height = reader.height();
  map.lengths.assign(size_t(map.width) * map.height, 0);
  TexelValues values;
  uint64_t sum = 0, nonempty = 0;
  for (uint32_t y = 0; y < map.height; ++y)
    for (uint32_t x = 0; x < map.width; ++x) {
      uint32_t& length = map.lengths[size_t(y) * map.width + x];
      for (uint32_t z = slice.value_or(0); z < (slice ? *slice + 1 : slices); ++z) {
        reader.read(x, y, z, values);
        length = std::max(length, uint32_t(values.codes.at(lists->count_channel)));
      }
      map.longest = std::max(map.longest, length);
      sum += length;
      nonempty += length > 0;
    }
  map.mean_nonempty = nonempty ? double(sum) / double(nonempty) : 0.0;
  return map;
}

std::array<uint8_t, 3> heat_colour(uint32_t length, uint32_t longest) {
  if (length == 0 || longest == 0) return {0, 0, 0};
  // Stops of the scale, from one light to the longest list.
  static constexpr std::array<std::array<double, 3>, 5> stops = {
      {{0.10, 0.10, 0.55}, {0.05, 0.45, 0.85}, {0.15, 0.75, 0.35}, {0.95, 0.85, 0.15}, {1.0, 1.0, 1.0}}};
  const double t = longest > 1 ? double(length - 1) / double(longest - 1) : 1.0;
  const double at = t * double(stops.size() - 1);
  const size_t i = std::min(size_t(at), stops.size() - 2);
  const double f = at - double(i);
  std::array<uint8_t, 3> rgb{};
  for (int c = 0; c < 3; ++c)
    rgb[c] = uint8_t(std::lround(255.0 * (stops[i][c] + (stops[i + 1][c] - stops[i][c]) * f)));
  return rgb;
}

Rgba8Image heatmap_picture(const ListHeatmap& map, uint32_t scale) {
  Rgba8Image image;
  image.width = map.width * scale;
  image.height = map.height * scale;
  image.pixels.assign(size_t(image.width) * image.height * 4, 255);
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const auto rgb = heat_colour(map.lengths[size_t(y / scale) * map.width + x / scale], map.longest);
      std::copy(rgb.begin(), rgb.end(), image.pixels.begin() + (size_t(y) * image.width + x) * 4);
    }
  return image;
}

}  // namespace nightcap
