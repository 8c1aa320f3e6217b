#include "inspect/decode.h"

#include <cmath>
#include <cstring>
#include <utility>

#include "passes/core/output_pixel.h"
#include "passes/lights/cluster_layout.h"
#include "passes/scene/scene.h"

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

nlohmann::ordered_json vector_json(const double* v, size_t n) { return std::vector<double>(v, v + n); }

double rec709_luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

void decode_kind(const ResourceRecord& record, const FrameRecord& frame, const TexelValues& texel,
                 nlohmann::ordered_json& out) {
  const std::vector<double>& v = texel.raw;
  switch (record.kind) {
    case ResourceKind::normal:
    case ResourceKind::packed_normal: {
      const std::array<double, 3> n = *stored_normal(record.kind, texel);
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      // The zero vector (a cleared target) has no direction.
      out["normal"] = length == 0.0 ? nlohmann::ordered_json(nullptr)
                                    : nlohmann::ordered_json{n[0] / length, n[1] / length, n[2] / length};
      out["stored_length"] = length;
      if (record.kind == ResourceKind::packed_normal)
        out["roughness"] = v[3];
      else if (v.size() > 3)
        out["hair"] = v[3] != 0.0;  // gbuffer.normal's 2-bit alpha marks hair
      return;
    }
    case ResourceKind::material:  // gbuffer.material: the emissive channel is log2(1 + L) / 16
      out["metalness"] = v[0];
      out["roughness"] = v[1];
      out["translucency"] = v[2];
      out["emissive_luminance"] = std::exp2(16.0 * v[3]) - 1.0;
      return;
    case ResourceKind::motion: {
      const auto pixels = motion_pixels(v[0], v[1], frame);
      out["motion_uv"] = {v[0], v[1]};
      out["motion_pixels"] = {pixels[0], pixels[1]};
      return;
    }
    case ResourceKind::depth_stencil: {
      out["device_depth"] = v[0];
      const std::optional<double> metres = linear_metres(v[0], frame);
      out["linear_m"] = metres ? nlohmann::ordered_json(*metres) : nlohmann::ordered_json("infinite (nothing drawn)");
      if (v.size() > 1) {
        const uint32_t stencil = uint32_t(texel.codes.at(0));
        out["stencil"] = stencil;
        out["class"] = stencil_class_name(stencil);
        out["flags"] = stencil_flags(stencil);
      }
      return;
    }
    case ResourceKind::linear_depth:
      out["linear_m"] = v[0];
      return;
    case ResourceKind::depth_minmax:
      out["min_m"] = v[0];
      out["max_m"] = v[1];
      return;
    case ResourceKind::stencil: {  // stencil.half: the tag of one full-resolution texel
      const uint32_t stencil = uint32_t(texel.codes.at(0));
      out["stencil"] = stencil;
      out["class"] = stencil_class_name(stencil);
      out["flags"] = stencil_flags(stencil);
      return;
    }
    case ResourceKind::mask:
      out["masked"] = texel.codes.at(0) != 0;
      return;
    case ResourceKind::hdr_colour:
      out["rgb"] = vector_json(v.data(), std::min<size_t>(3, v.size()));
      if (v.size() >= 3) out["luminance"] = rec709_luminance(v[0], v[1], v[2]);
      return;
    case ResourceKind::colour:
      out["rgb_linear"] = vector_json(v.data(), std::min<size_t>(3, v.size()));
      if (v.size() > 3) out["alpha"] = v[3];
      return;
    case ResourceKind::light_clusters:  // the list itself is in lights.cluster_indices (inspect's pixel reads it)
      out["offset"] = texel.codes.at(0);
      out["count"] = texel.codes.at(1);
      return;
    case ResourceKind::lookup_table:
    case ResourceKind::texture:
    case ResourceKind::buffer:
    case ResourceKind::draw_list:
      return;  // their raw values are what they hold
  }
}

}  // namespace

std::string stencil_class_name(uint32_t stencil) {
  static const std::pair<uint8_t, const char*> kClasses[] = {
      {stencil::plain, "plain"},     {stencil::road, "road"}, {stencil::body, "body"},      {stencil::face, "face"},
      {stencil::vehicle, "vehicle"}, {stencil::hair, "hair"}, {stencil::foliage, "foliage"}};
  for (const auto& [tag, name] : kClasses)
    if ((stencil & ~uint32_t(stencil::moving)) == tag) return name;
  return "unknown";
}

std::vector<std::string> stencil_flags(uint32_t stencil) {
  std::vector<std::string> flags;
  if (stencil & stencil::moving) flags.push_back("moving");
  return flags;
}

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

uint32_t cluster_tile_size(const ResourceRecord& record, const FrameRecord& frame) {
  for (const PassRecord& pass : frame.passes)
    for (const ResourceRecord& out : pass.outputs)
      if (out.resource == record.resource && out.hash == record.hash) {
        auto tile = pass.params.find("tile_size");
        if (tile != pass.params.end() && tile->second >= 1) return uint32_t(tile->second);
      }
  return kClusterTile;
}

TexelAddress texel_for_output_pixel(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
                                    const Subimage& subimage) {
  check_subimage(record, subimage);
  if (x >= frame.width || y >= frame.height)
    throw InspectError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                       std::to_string(frame.width) + "x" + std::to_string(frame.height) + " output");
  const uint32_t width = mip_size(record.extent.width, subimage.mip);
  const uint32_t height = mip_size(record.extent.height, subimage.mip);
  // Froxels are whole tiles from the top left, the last row and column cut short.
  if (record.kind == ResourceKind::light_clusters) {
    const uint32_t tile = cluster_tile_size(record, frame);
    return {std::min(x / tile, width - 1), std::min(y / tile, height - 1), subimage.mip, subimage.layer,
            subimage.slice};
  }
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

std::optional<std::array<double, 3>> stored_normal(ResourceKind kind, const TexelValues& texel) {
  const std::vector<double>& v = texel.raw;
  if (kind == ResourceKind::normal) return std::array<double, 3>{v[0] * 2 - 1, v[1] * 2 - 1, v[2] * 2 - 1};
  if (kind == ResourceKind::packed_normal) {
    const std::vector<uint64_t>& c = texel.codes;
    return std::array<double, 3>{c[0] * (2.0 / 255.0) - 1, c[1] * (2.0 / 255.0) - 1, c[2] * (2.0 / 255.0) - 1};
  }
  return std::nullopt;
}

std::optional<double> linear_metres(double device_depth, const FrameRecord& frame) {
  if (!(device_depth > 0.0)) return std::nullopt;
  return frame.camera.znear / device_depth;
}

std::array<double, 2> motion_pixels(double u, double v, const FrameRecord& frame) {
  return {u * frame.width, v * frame.height};
}

PixelReading read_pixel(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                        const TexelAddress& texel) {
  PixelReading reading{texel, read_texel(record, raw, texel)};
  decode_kind(record, frame, reading.values, reading.decoded);
  return reading;
}

uint64_t buffer_elements(const BufferSchema& schema, uint64_t bytes) { return bytes / schema.stride; }

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
