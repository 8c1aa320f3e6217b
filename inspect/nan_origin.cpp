#include "inspect/nan_origin.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "passes/core/output_pixel.h"

namespace nightcap {
namespace {

// Byte offsets, ascending, of a version's non-finite values: each texel with a non-finite channel
// (of the float aspect), each non-finite float component of a buffer. Empty for nearly every
// version, so one is cheap to keep for every version the search has seen.
using Positions = std::vector<uint64_t>;

bool holds_floats(const ResourceRecord& record, const BufferSchema* schema) {
  if (record.is_buffer)
    return schema && std::any_of(schema->fields.begin(), schema->fields.end(), [](const SchemaField& f) {
             return f.scalar == Scalar::f32 || f.scalar == Scalar::f64;
           });
  return is_float(*format_info(record.format));
}

// The float aspect (colour, or depth before the stencil plane) is one run of bytes at the start
// of the raw layout, so it is read a texel at a time on the bits, without decoding.
template <typename Word, typename NonFinite>
void scan_texels(std::span<const uint8_t> plane, uint32_t texel_bytes, NonFinite non_finite, Positions& found) {
  for (uint64_t texel = 0; texel + texel_bytes <= plane.size(); texel += texel_bytes)
    for (uint32_t at = 0; at < texel_bytes; at += sizeof(Word)) {
      Word word;
      std::memcpy(&word, plane.data() + texel + at, sizeof(Word));
      if (non_finite(word)) {
        found.push_back(texel);
        break;
      }
    }
}

Positions image_positions(const ResourceRecord& record, std::span<const uint8_t> raw) {
  const FormatInfo format = *format_info(record.format);
  const std::span<const uint8_t> plane = raw.first(raw_subresource_offset(format, record.extent, 1, 0, 0));
  Positions found;
  // A float is non-finite when its exponent bits are all ones.
  switch (format.encoding) {
    case ChannelEncoding::sfloat32:
    case ChannelEncoding::depth32_stencil8:
      scan_texels<uint32_t>(
          plane, format.texel_bytes, [](uint32_t w) { return (w & 0x7F800000u) == 0x7F800000u; }, found);
      break;
    case ChannelEncoding::sfloat16:
      scan_texels<uint16_t>(
          plane, format.texel_bytes, [](uint16_t h) { return (h & 0x7C00u) == 0x7C00u; }, found);
      break;
    case ChannelEncoding::packed_b10g11r11:  // exponents: r bits 6–10, g 17–21, b 27–31
      scan_texels<uint32_t>(
          plane, format.texel_bytes,
          [](uint32_t w) {
            return (w & (0x1Fu << 6)) == (0x1Fu << 6) || (w & (0x1Fu << 17)) == (0x1Fu << 17) ||
                   (w & (0x1Fu << 27)) == (0x1Fu << 27);
          },
          found);
      break;
    default:
      break;
  }
  return found;
}

Positions buffer_positions(const BufferSchema& schema, std::span<const uint8_t> raw) {
  Positions found;
  if (schema.stride == 0) return found;
  const uint64_t elements = raw.size() / schema.stride;
  for (uint64_t element = 0; element < elements; ++element)
    for (const SchemaField& field : schema.fields) {
      if (field.scalar != Scalar::f32 && field.scalar != Scalar::f64) continue;
      for (uint32_t c = 0; c < field.count; ++c)
        if (!std::isfinite(read_component(raw, schema.stride, element, field, c)))
          found.push_back(element * schema.stride + field.offset + c * (field.bytes() / field.count));
    }
  std::sort(found.begin(), found.end());  // schema_from_json does not order fields by offset
  return found;
}

NonFiniteTexel texel_at(const ResourceRecord& record, std::span<const uint8_t> raw, uint64_t position,
                        const FrameRecord& frame) {
  const FormatInfo format = *format_info(record.format);
  const ImageExtent& extent = record.extent;
  for (uint32_t mip = 0; mip < extent.mips; ++mip)
    for (uint32_t layer = 0; layer < extent.layers; ++layer) {
      const uint64_t offset = raw_subresource_offset(format, extent, 0, mip, layer);
      const uint64_t bytes = raw_subresource_bytes(format, extent, 0, mip);
      if (position < offset || position >= offset + bytes) continue;
      const uint32_t width = mip_size(extent.width, mip), height = mip_size(extent.height, mip);
      const uint64_t index = (position - offset) / format.texel_bytes;
      NonFiniteTexel texel;
      texel.x = uint32_t(index % width);
      texel.y = uint32_t(index / width % height);
      texel.slice = uint32_t(index / width / height);
      texel.mip = mip;
      texel.layer = layer;
      texel.pixel_x = first_pixel_over_texel(texel.x, width, frame.width);
      texel.pixel_y = first_pixel_over_texel(texel.y, height, frame.height);
      float value[4];
      decode_texel(format, 0, raw.subspan(offset, bytes), index, value);
      texel.values.assign(value, value + aspect_channels(format, 0));
      return texel;
    }
  return {};  // unreachable: positions come from the plane the loops cover
}

NonFiniteField field_at(const BufferSchema& schema, std::span<const uint8_t> raw, uint64_t position) {
  const uint64_t element = position / schema.stride, within = position % schema.stride;
  for (const SchemaField& field : schema.fields)
    if (within >= field.offset && within < uint64_t(field.offset) + field.bytes()) {
      const uint32_t component = uint32_t((within - field.offset) / (field.bytes() / field.count));
      return {element, component_name(field, component), read_component(raw, schema.stride, element, field, component)};
    }
  return {};  // unreachable: positions come from the fields
}

class Search {
 public:
  Search(std::span<const FrameRecord> frames, const LoadVersion& load, size_t limit) : load_(load), limit_(limit) {
    for (const FrameRecord& frame : frames)
      for (const PassRecord& pass : frame.passes)
        for (const ResourceRecord& out : pass.outputs)
          if (out.schema) schemas_.emplace(key(out), &*out.schema);
  }

  void pass(const FrameRecord& frame, size_t frame_position, size_t pass_index, std::vector<NanOrigin>& origins) {
    const PassRecord& pass = frame.passes[pass_index];
    NanOrigin came_in{NanOrigin::How::came_in, frame_position, pass_index, {}};
    bool read_non_finite = false;
    for (const ResourceRecord& in : pass.inputs) {
      const bool from_outside = !written_.count(key(in)) && looked_at_.insert(key(in)).second;
      read_non_finite = !positions(in, from_outside ? &came_in : nullptr, frame).empty() || read_non_finite;
    }
    if (!came_in.resources.empty()) origins.push_back(std::move(came_in));

    // Every input finite, the version of a resource it modified among them: all an output's
    // non-finite values were born here.
    NanOrigin born{NanOrigin::How::born, frame_position, pass_index, {}};
    for (const ResourceRecord& out : pass.outputs) {
      written_.insert(key(out));
      positions(out, read_non_finite ? nullptr : &born, frame);
    }
    if (!born.resources.empty()) origins.push_back(std::move(born));
  }

 private:
  // Equal bytes read as another format or schema are another version.
  static std::string key(const ResourceRecord& r) {
    return r.hash + (r.is_buffer ? "/buffer/" + r.resource : "/" + std::to_string(int(r.format)));
  }

  const BufferSchema* schema_of(const ResourceRecord& r) const {
    if (r.schema) return &*r.schema;
    auto found = schemas_.find(key(r));
    return found == schemas_.end() ? nullptr : found->second;
  }

  // The non-finite positions of version `r`, loaded and scanned the first time it is asked for.
  // Where `report` is given, they are added to it with their values.
  const Positions& positions(const ResourceRecord& r, NanOrigin* report, const FrameRecord& frame) {
    const std::string k = key(r);
    const auto known = scanned_.find(k);
    if (known != scanned_.end() && (!report || known->second.empty())) return known->second;
    const BufferSchema* schema = schema_of(r);
    if (!holds_floats(r, schema)) return scanned_[k];
    // A version seen before is loaded again only to list its values, not scanned again.
    const std::vector<uint8_t> raw = load_(r);
    const Positions& all = known != scanned_.end()
                               ? known->second
                               : (scanned_[k] = r.is_buffer ? buffer_positions(*schema, raw) : image_positions(r, raw));
    if (!report || all.empty()) return all;
    NonFiniteValues values{&r, all.size(), {}, {}};
    for (size_t i = 0; i < std::min(all.size(), limit_); ++i)
      if (r.is_buffer)
        values.fields.push_back(field_at(*schema, raw, all[i]));
      else
        values.texels.push_back(texel_at(r, raw, all[i], frame));
    report->resources.push_back(std::move(values));
    return all;
  }

  const LoadVersion& load_;
  size_t limit_;
  std::map<std::string, const BufferSchema*> schemas_;
  std::map<std::string, Positions> scanned_;
  std::set<std::string> written_;    // versions a searched pass wrote
  std::set<std::string> looked_at_;  // versions from outside, reported where first read
};

}  // namespace

std::vector<NanOrigin> find_nan_origins(std::span<const FrameRecord> frames, std::optional<size_t> only_frame,
                                        const LoadVersion& load, size_t limit) {
  Search search(frames, load, limit);
  std::vector<NanOrigin> origins;
  for (size_t f = only_frame.value_or(0); f < (only_frame ? *only_frame + 1 : frames.size()); ++f)
    for (size_t p = 0; p < frames[f].passes.size(); ++p) search.pass(frames[f], f, p, origins);
  return origins;
}

}  // namespace nightcap
