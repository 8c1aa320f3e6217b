// Pictures of resources for people, drawn as each kind of data says, shared by `inspect export`
// and the HTML reports: normals as colour, depth on a log scale, motion on a colour wheel,
// stencil tags as a palette, HDR colour tonemapped.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "captures/capture.h"
#include "images/images.h"
#include "inspect/decode.h"

namespace nightcap {

// Which aspect of a depth-stencil image to draw; other formats have only `depth_or_colour`.
enum class VisualAspect { depth_or_colour, stencil };

// The nearest and farthest of the distances a picture is drawn between (drawn white and black).
struct DistanceRange {
  double nearest = 0, farthest = 0;
};

// The nearest and farthest distance that `record`'s kind draws in `subimage`, leaving out the
// texels with nothing there (its `draw` gives 0: the clear value of depth, the sky, a shadow
// map where no caster was drawn) and those not finite; nullopt for kinds not drawn as distances
// and for subimages with nothing there.
std::optional<DistanceRange> distance_range(const ResourceRecord& record, std::span<const uint8_t> raw,
                                            const FrameRecord& frame, const Subimage& subimage);

// One subresource of an image as RGBA8, each texel drawn as its kind's registered `draw` says
// (passes/core/resource_kind.h): display values as they are, light sRGB-encoded, distances on a
// log scale from the nearest (white) to the farthest (black) in the image with nothing there
// black, motion on a colour wheel (hue from the direction, brightness from the length against
// the longest in the image). A kind that registers no drawing shows its channels as they are,
// clamped to [0, 1] (one channel: grey). The stencil aspect is drawn by the kind's
// `draw_stencil` (the tag as grey where it has none). `shown`: the range to draw distances
// between instead of the image's own (the layers of a shadow map drawn on one scale), with
// distances outside it clamped.
Rgba8Image visualise(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                     const Subimage& subimage, VisualAspect aspect,
                     const std::optional<DistanceRange>& shown = std::nullopt);

// The 8-bit sRGB code of a linear value x in [0, 1]: round(255 · linear_to_srgb(x)), looked up
// instead of computed with a pow per channel (a quarter of drawing a colour picture). Each
// code's smallest input is found once by bisection over the floats of [0, 1], whose bits are in
// the order of their values.
uint8_t srgb_code(float x);

}  // namespace nightcap
