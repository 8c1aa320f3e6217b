// A resource's contents in its own terms: one pixel of an image decoded as its kind's registered
// `describe` says (passes/core/resource_kind.h: a packed normal as a unit vector, device depth as
// metres, a stencil tag as its class, motion in pixels), and a buffer decoded by the schema its
// pass declared. The raw values are
// always kept beside the decoded ones, so a reader can check the decoding.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

// A request the capture cannot answer (unknown pass or resource, a pixel outside the image):
// the message is one line for the user.
struct InspectError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One 2D image of a resource: a mip of a layer and, in a 3D image, one depth slice of that mip.
struct Subimage {
  uint32_t mip = 0, layer = 0, slice = 0;
};
// Throws InspectError naming what `record` lacks: the mip, the layer, or the slice (a 2D image
// has slice 0 only).
void check_subimage(const ResourceRecord& record, const Subimage& subimage);

// Where a pixel of the frame's output lands in one subimage of an image.
struct TexelAddress {
  uint32_t x = 0, y = 0, mip = 0, layer = 0, slice = 0;
};

// Throws InspectError unless `direction` is finite and not zero.
void check_direction(const std::array<double, 3>& direction);

// The texel of cube map `record` (its layers cube faces) at `mip` that world direction `direction`
// falls in, by Vulkan's cube map face selection: the major axis picks the face (the layer). Throws
// InspectError when `record` is no cube map or the direction is zero or not finite.
TexelAddress cube_texel(const ResourceRecord& record, const std::array<double, 3>& direction, uint32_t mip);

// The pass of `frame` that wrote this version of `record`; null if none did.
const PassRecord* writer_of(const ResourceRecord& record, const FrameRecord& frame);

// Pixels on a side of the output tile a texel covers, for kinds whose texels are tiles (froxels):
// the writer's parameter its kind names, or the kind's fallback where the writer recorded none.
std::optional<uint32_t> output_tile_size(const ResourceRecord& record, const FrameRecord& frame);

// Output coordinates (full resolution) scaled to `subimage` of `record`: half-resolution
// resources, mips and fixed-size tables take the texel that covers the same place of the
// screen; tiled kinds (froxels), the tile the pixel lies in. Throws InspectError when the pixel or the
// subimage is outside.
TexelAddress texel_for_output_pixel(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
                                    const Subimage& subimage);

TexelValues read_texel(const ResourceRecord& record, std::span<const uint8_t> raw, const TexelAddress& texel);

// read_texel for every texel of one subresource: the format and the planes are looked up once,
// and `values` keeps its storage from one texel to the next (a picture reads a million).
class SubresourceReader {
 public:
  SubresourceReader(const ResourceRecord& record, std::span<const uint8_t> raw, uint32_t mip, uint32_t layer);
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  void read(uint32_t x, uint32_t y, uint32_t slice, TexelValues& values) const;

 private:
  FormatInfo format_;
  uint32_t width_, height_;
  std::array<std::span<const uint8_t>, 2> planes_;
};

// What a kind's decoding needs of the frame: its camera and output size.
KindFrame kind_frame(const FrameRecord& frame);

struct PixelReading {
  TexelAddress texel;
  TexelValues values;
  // What the texel means for the resource's kind, in order: "normal", "linear_m", "class", …
  nlohmann::ordered_json decoded = nlohmann::ordered_json::object();
};

// `raw`: the record's bytes in format.h's raw layout. The frame supplies the camera (depth
// linearisation) and the output size (motion in pixels).
PixelReading read_pixel(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                        const TexelAddress& texel);

// Element `element` of a buffer decoded by `schema`, field by field (values exact: every 32-bit
// value and every f64 fits a double).
nlohmann::ordered_json decode_buffer_element(const BufferSchema& schema, std::span<const uint8_t> raw,
                                             uint64_t element);
uint64_t buffer_elements(const BufferSchema& schema, uint64_t bytes);
// The schema of the buffer version `record`: its own, or the one recorded with the output of
// `frame` that wrote it (inputs carry none); null when its writer declared none.
const BufferSchema* schema_of(const ResourceRecord& record, const FrameRecord& frame);

}  // namespace nightcap
