#include "inspect/decode.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "passes/core/output_pixel.h"

namespace nightcap {

namespace {

using E = ChannelEncoding;

uint32_t load_u32(std::span<const uint8_t> bytes, uint64_t offset) {
  uint32_t value;
  std::memcpy(&value, bytes.data() + offset, 4);
  return value;
}

uint16_t load_u16(std::span<const uint8_t> bytes, uint64_t offset) {
  uint16_t value;
  std::memcpy(&value, bytes.data() + offset, 2);
  return value;
}

// Appends the integer codes one texel of one aspect stores to `codes` (nothing for float
// channels).
void append_stored_codes(const FormatInfo& format, uint32_t aspect, std::span<const uint8_t> plane, uint64_t index,
                         std::vector<uint64_t>& codes) {
  const uint64_t base = index * aspect_texel_bytes(format, aspect);
  switch (format.encoding) {
    case E::unorm8:
    case E::srgb8:
    case E::uint8:
      for (uint32_t c = 0; c < format.channels; ++c) codes.push_back(plane[base + c]);
      break;
    case E::unorm16:
    case E::uint16:
      for (uint32_t c = 0; c < format.channels; ++c) codes.push_back(load_u16(plane, base + 2 * c));
      break;
    case E::uint32:
      for (uint32_t c = 0; c < format.channels; ++c) codes.push_back(load_u32(plane, base + 4 * c));
      break;
    case E::packed_a2b10g10r10: {
      const uint32_t w = load_u32(plane, base);
      codes.insert(codes.end(), {w & 1023u, (w >> 10) & 1023u, (w >> 20) & 1023u, w >> 30});
      break;
    }
    case E::packed_b10g11r11: {
      const uint32_t w = load_u32(plane, base);
      codes.insert(codes.end(), {w & 0x7ffu, (w >> 11) & 0x7ffu, w >> 22});
      break;
    }
    case E::depth32_stencil8:
      if (aspect == 1) codes.push_back(plane[base]);
      break;
    case E::sfloat16:
    case E::sfloat32:
      break;
  }
}

}  // namespace

void check_subimage(const ResourceRecord& record, const Subimage& subimage) {
  if (record.is_buffer) throw InspectError(record.resource + " is a buffer: use `buffer " + record.resource + "`");
  if (subimage.mip >= record.extent.mips)
    throw InspectError(record.resource + " has " + std::to_string(record.extent.mips) + " mip(s): no mip " +
                       std::to_string(subimage.mip));
  if (subimage.layer >= record.extent.layers)
    throw InspectError(record.resource + " has " + std::to_string(record.extent.layers) + " layer(s): no layer " +
                       std::to_string(subimage.layer));
  const uint32_t slices = mip_size(record.extent.depth, subimage.mip);
  if (subimage.slice >= slices)
    throw InspectError(record.resource + " has " + std::to_string(slices) + " slice(s) at mip " +
                       std::to_string(subimage.mip) + ": no slice " + std::to_string(subimage.slice));
}

void check_direction(const std::array<double, 3>& d) {
  const double ax = std::abs(d[0]), ay = std::abs(d[1]), az = std::abs(d[2]);
  if (!(std::isfinite(ax) && std::isfinite(ay) && std::isfinite(az)) || std::max({ax, ay, az}) == 0.0)
    throw InspectError("direction: expected a finite direction that is not zero");
}

TexelAddress cube_texel(const ResourceRecord& record, const std::array<double, 3>& d, uint32_t mip) {
  if (!record.cube) throw InspectError(record.resource + " is not a cube map: use `pixel`");
  check_subimage(record, {mip, 0, 0});
  check_direction(d);
  const double ax = std::abs(d[0]), ay = std::abs(d[1]), az = std::abs(d[2]);
  // Vulkan's table: the face, then sc and tc over the major axis's magnitude.
  uint32_t face;
  double sc, tc, major;
  if (ax >= ay && ax >= az) {
    face = d[0] >= 0 ? 0 : 1;
    sc = d[0] >= 0 ? -d[2] : d[2];
    tc = -d[1];
    major = ax;
  } else if (ay >= az) {
    face = d[1] >= 0 ? 2 : 3;
    sc = d[0];
    tc = d[1] >= 0 ? d[2] : -d[2];
    major = ay;
  } else {
    face = d[2] >= 0 ? 4 : 5;
    sc = d[2] >= 0 ? d[0] : -d[0];
    tc = -d[1];
    major = az;
  }
  const uint32_t side = mip_size(record.extent.width, mip);
  const auto texel = [&](double c) {
    return std::min(uint32_t(std::max(0.5 * (c / major + 1.0) * side, 0.0)), side - 1);
  };
  return {texel(sc), texel(tc), mip, face, 0};
}

const PassRecord* writer_of(const ResourceRecord& record, const FrameRecord& frame) {
  for (const PassRecord& pass : frame.passes)
    for (const ResourceRecord& out : pass.outputs)
      if (out.resource == record.resource && out.hash == record.hash) return &pass;
  return nullptr;
}

std::optional<uint32_t> output_tile_size(const ResourceRecord& record, const FrameRecord& frame) {
  const std::optional<OutputTiles>& tiles = kind_info(record.kind).tiles;
  if (!tiles) return std::nullopt;
  if (const PassRecord* writer = writer_of(record, frame)) {
    const auto side = writer->params.find(tiles->parameter);
    if (side != writer->params.end() && side->second >= 1) return uint32_t(side->second);
  }
  return tiles->fallback;
}

TexelAddress texel_for_output_pixel(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
                                    const Subimage& subimage) {
  check_subimage(record, subimage);
  if (x >= frame.width || y >= frame.height)
    throw InspectError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                       std::to_string(frame.width) + "x" + std::to_string(frame.height) + " output");
  const uint32_t width = mip_size(record.extent.width, subimage.mip);
  const uint32_t height = mip_size(record.extent.height, subimage.mip);
  // Tiles are whole from the top left, the last row and column cut short.
  if (const std::optional<uint32_t> tile = output_tile_size(record, frame))
    return {std::min(x / *tile, width - 1), std::min(y / *tile, height - 1), subimage.mip, subimage.layer,
            subimage.slice};
  return {texel_under_pixel(x, frame.width, width), texel_under_pixel(y, frame.height, height), subimage.mip,
          subimage.layer, subimage.slice};
}

SubresourceReader::SubresourceReader(const ResourceRecord& record, std::span<const uint8_t> raw, uint32_t mip,
                                     uint32_t layer)
    : format_(*format_info(record.format)),
      width_(mip_size(record.extent.width, mip)),
      height_(mip_size(record.extent.height, mip)) {
  for (uint32_t aspect = 0; aspect < aspect_count(format_); ++aspect)
    planes_[aspect] = raw.subspan(raw_subresource_offset(format_, record.extent, aspect, mip, layer),
                                  raw_subresource_bytes(format_, record.extent, aspect, mip));
}

void SubresourceReader::read(uint32_t x, uint32_t y, uint32_t slice, TexelValues& values) const {
  values.raw.clear();
  values.codes.clear();
  const uint64_t index = (uint64_t(slice) * height_ + y) * width_ + x;
  for (uint32_t aspect = 0; aspect < aspect_count(format_); ++aspect) {
    float decoded[4] = {};
    decode_texel(format_, aspect, planes_[aspect], index, decoded);
    values.raw.insert(values.raw.end(), decoded, decoded + aspect_channels(format_, aspect));
    append_stored_codes(format_, aspect, planes_[aspect], index, values.codes);
  }
  // Integer channels wider than a float's mantissa are exact only as codes.
  if (format_.encoding == E::uint32)
    for (size_t c = 0; c < values.codes.size(); ++c) values.raw[c] = double(values.codes[c]);
}

TexelValues read_texel(const ResourceRecord& record, std::span<const uint8_t> raw, const TexelAddress& texel) {
  TexelValues values;
  SubresourceReader(record, raw, texel.mip, texel.layer).read(texel.x, texel.y, texel.slice, values);
  return values;
}

KindFrame kind_frame(const FrameRecord& frame) { return {frame.camera.znear, frame.width, frame.height}; }

PixelReading read_pixel(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                        const TexelAddress& texel) {
  PixelReading reading{texel, read_texel(record, raw, texel)};
  const KindInfo& kind = kind_info(record.kind);
  if (kind.describe) kind.describe(reading.values, kind_frame(frame), reading.decoded);
  return reading;
}

uint64_t buffer_elements(const BufferSchema& schema, uint64_t bytes) { return bytes / schema.stride; }

const BufferSchema* schema_of(const ResourceRecord& record, const FrameRecord& frame) {
  if (record.schema) return &*record.schema;
  for (const PassRecord& p : frame.passes)
    for (const ResourceRecord& r : p.outputs)
      if (r.resource == record.resource && r.hash == record.hash && r.schema) return &*r.schema;
  return nullptr;
}

nlohmann::ordered_json decode_buffer_element(const BufferSchema& schema, std::span<const uint8_t> raw,
                                             uint64_t element) {
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
  for (const SchemaField& field : schema.fields) {
    // Integers as integers: a 32-bit mask read as a double would print rounded.
    nlohmann::ordered_json values = nlohmann::ordered_json::array();
    for (uint32_t c = 0; c < field.count; ++c) {
      const double v = read_component(raw, schema.stride, element, field, c);
      if (field.scalar == Scalar::u32)
        values.push_back(uint64_t(v));
      else if (field.scalar == Scalar::i32)
        values.push_back(int64_t(v));
      else
        values.push_back(v);
    }
    fields[field.name] = field.count == 1 ? values[0] : values;
  }
  return fields;
}

}  // namespace nightcap
