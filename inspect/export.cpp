#include "inspect/export.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <vector>

#include "inspect/decode.h"

namespace nightcap {

void write_values_exr(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
                      uint32_t mip, uint32_t layer) {
  const FormatInfo format = *format_info(record.format);
  const uint32_t width = mip_size(record.extent.width, mip), height = mip_size(record.extent.height, mip);
  const uint64_t texels = uint64_t(width) * height;
  std::vector<std::string> names;
  std::vector<std::vector<float>> planes;
  for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect) {
    const std::span<const uint8_t> plane =
        raw.subspan(raw_subresource_offset(format, record.extent, aspect, mip, layer),
                    raw_subresource_bytes(format, record.extent, aspect, mip));
    const uint32_t channels = aspect_channels(format, aspect);
    const size_t first = planes.size();
    for (uint32_t c = 0; c < channels; ++c) {
      names.push_back(format.is_depth ? (aspect == 0 ? "Z" : "S") : std::string(1, "RGBA"[c]));
      planes.emplace_back(texels);
    }
    for (uint64_t i = 0; i < texels; ++i) {
      float values[4] = {};
      decode_texel(format, aspect, plane, i, values);
      for (uint32_t c = 0; c < channels; ++c) planes[first + c][i] = values[c];
    }
  }
  try {
    Imf::Header header(static_cast<int>(width), static_cast<int>(height));
    Imf::FrameBuffer buffer;
    for (size_t c = 0; c < names.size(); ++c) {
      header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
      buffer.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[c].data()), sizeof(float),
                                         sizeof(float) * width));
    }
    Imf::OutputFile out(file.c_str(), header);
    out.setFrameBuffer(buffer);
    out.writePixels(int(height));
  } catch (const std::exception& e) {
    throw InspectError(file.string() + ": cannot write: " + e.what());
  }
}

}  // namespace nightcap
