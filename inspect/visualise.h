// Pictures of resources for people, one visualisation per kind of data, shared by `inspect
// export` and (later) the HTML report: normals as colour, depth linearised, motion on a colour
// wheel, stencil tags as a palette, HDR colour tonemapped.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "captures/capture.h"
#include "images/images.h"
#include "inspect/decode.h"

namespace nightcap {

// Which aspect of a depth-stencil image to draw; other formats have only `depth_or_colour`.
enum class VisualAspect { depth_or_colour, stencil };

// One subresource of an image as RGBA8 (sRGB-encoded where it shows light or colour):
// - normal, packed_normal: 0.5·n + 0.5 of the unit vector; a zero vector is black.
// - depth_stencil, linear_depth, depth_minmax (its min): linear metres on a log scale from the
//   nearest (white) to the farthest (black) finite depth in the image; nothing drawn is black.
// - stencil (a depth-stencil's stencil aspect, or a stencil-kind image): the class's palette
//   colour (plain black, road grey, body and face skin tones, vehicle blue, hair brown, foliage
//   green, unknown magenta); the moving flag brightens it.
// - mask: white where set, black elsewhere.
// - motion: hue from the direction, saturation and brightness from the length relative to the
//   longest motion in the image (no motion: black).
// - light_clusters: one depth slice, each froxel's count c as grey c / (c + 8) (none: black).
// - hdr_colour: Reinhard x / (1 + x) per channel, then sRGB.
// - colour: its linear values sRGB-encoded; material and the rest: channels as they are,
//   clamped to [0, 1] (one channel: grey).
Rgba8Image visualise(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                     const Subimage& subimage, VisualAspect aspect);

// The 8-bit sRGB code of a linear value x in [0, 1]: round(255 · linear_to_srgb(x)), looked up
// instead of computed with a pow per channel (a quarter of drawing a colour picture). Each
// code's smallest input is found once by bisection over the floats of [0, 1], whose bits are in
// the order of their values.
uint8_t srgb_code(float x);

// Palette entry of a stencil value (see above), RGB.
std::array<uint8_t, 3> stencil_colour(uint32_t stencil);

}  // namespace nightcap
