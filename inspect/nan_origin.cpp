#include "inspect/nan_origin.h"

#include <cmath>

#include "passes/core/output_pixel.h"

namespace nightcap {
namespace {

bool same_shape(const ResourceRecord& a, const ResourceRecord& b) {
  const ImageExtent &x = a.extent, &y = b.extent;
  return a.format == b.format && x.width == y.width && x.height == y.height && x.depth == y.depth && x.mips == y.mips &&
         x.layers == y.layers;
}

bool finite(const float* channels, uint32_t count) {
  for (uint32_t c = 0; c < count; ++c)
    if (!std::isfinite(channels[c])) return false;
  return true;
}

// `before`: the version the pass started from (it modified the resource), or null when the pass
// wrote it fresh.
NonFiniteBirths births(const std::vector<uint8_t>& now, const std::vector<uint8_t>* before,
                       const ResourceRecord& record, const FrameRecord& frame, size_t limit) {
  const FormatInfo format = *format_info(record.format);
  const ImageExtent& extent = record.extent;
  NonFiniteBirths found;
  found.resource = &record;
  for (uint32_t mip = 0; mip < extent.mips; ++mip) {
    const uint32_t width = mip_size(extent.width, mip), height = mip_size(extent.height, mip);
    const uint64_t texels = uint64_t(width) * height * mip_size(extent.depth, mip);
    for (uint32_t layer = 0; layer < extent.layers; ++layer) {
      const uint64_t offset = raw_subresource_offset(format, extent, 0, mip, layer);
      const uint64_t bytes = raw_subresource_bytes(format, extent, 0, mip);
      const std::span<const uint8_t> plane = std::span(now).subspan(offset, bytes);
      for (uint64_t index = 0; index < texels; ++index) {
        float value[4], previous[4];
        decode_texel(format, 0, plane, index, value);
        if (finite(value, format.channels)) continue;
        if (before) {
          decode_texel(format, 0, std::span(*before).subspan(offset, bytes), index, previous);
          if (!finite(previous, format.channels)) continue;
        }
        if (found.count++ >= limit) continue;
        NonFiniteTexel texel;
        texel.x = uint32_t(index % width);
        texel.y = uint32_t(index / width % height);
        texel.slice = uint32_t(index / width / height);
        texel.mip = mip;
        texel.layer = layer;
        texel.pixel_x = first_pixel_over_texel(texel.x, width, frame.width);
        texel.pixel_y = first_pixel_over_texel(texel.y, height, frame.height);
        texel.values.assign(value, value + format.channels);
        found.first.push_back(std::move(texel));
      }
    }
  }
  return found;
}

}  // namespace

std::optional<NanOrigin> find_nan_origin(InspectSession& session, size_t limit) {
  const FrameRecord& frame = session.frame();
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    const PassRecord& pass = frame.passes[i];
    if (!pass.ran) continue;
    NanOrigin origin{i, {}};
    for (const ResourceRecord& out : pass.outputs) {
      if (out.is_buffer || !is_float_colour(*format_info(out.format))) continue;
      const ResourceRecord* before = nullptr;
      for (const ResourceRecord& in : pass.inputs)
        if (in.resource == out.resource && same_shape(in, out)) before = &in;
      if (before && before->hash == out.hash) continue;  // unchanged: nothing was born here
      NonFiniteBirths found = births(session.load(out), before ? &session.load(*before) : nullptr, out, frame, limit);
      if (found.count) origin.outputs.push_back(std::move(found));
    }
    if (!origin.outputs.empty()) return origin;
  }
  return std::nullopt;
}

}  // namespace nightcap
