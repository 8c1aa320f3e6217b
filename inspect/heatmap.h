// An image whose texels index lists (its kind registers TexelLists: lights.clusters) as a heat map
// of list lengths, for `inspect export RESOURCE --heatmap`: where the froxel lists are long, and
// so where lighting.tiled spends its time.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "captures/capture.h"
#include "images/images.h"

namespace nightcap {

// Per texel column (a cluster tile), the longest list over its depth slices, or the list of one
// slice.
struct ListHeatmap {
  uint32_t width = 0, height = 0;  // texels (cluster tiles)
  std::vector<uint32_t> lengths;   // row-major
  uint32_t longest = 0;
  double mean_nonempty = 0;  // over tiles with a list
};

// Throws InspectError when the resource's texels index no lists or `slice` is past it.
ListHeatmap list_heatmap(const ResourceRecord& record, std::span<const uint8_t> raw, std::optional<uint32_t> slice);

// Each tile as a `scale`×`scale` block (the cluster tile's size in pixels, so the picture lies
// over the frame it came from) on a colour scale from dark blue (one light) through green and
// yellow to white (the longest list); an empty tile is black.
Rgba8Image heatmap_picture(const ListHeatmap& map, uint32_t scale);

// The colour of a list `length` long in a map whose longest list is `longest`.
std::array<uint8_t, 3> heat_colour(uint32_t length, uint32_t longest);

}  // namespace nightcap
