#include "captures/blob_codec.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>
#include <zstd.h>

#include <cstring>
#include <fstream>
#include <mutex>
#include <thread>

namespace nightcap {
namespace {

// How one aspect of a format lands in EXR: the channel type and names, and how many bytes
// of raw data each EXR sample holds (UINT samples are 4 bytes wide, so narrower codes are
// widened on write and narrowed on read).
struct Layout {
  Imf::PixelType type;
  std::vector<std::string> channels;
  uint32_t raw_bytes_per_channel;  // 0: one packed 32-bit word for all channels
};

Layout layout_of(const FormatInfo& format, uint32_t aspect) {
  using E = ChannelEncoding;
  static const std::vector<std::string> names[5] = {{}, {"Y"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  switch (format.encoding) {
    case E::sfloat16: return {Imf::HALF, names[format.channels], 2};
    case E::sfloat32: return {Imf::FLOAT, format.is_depth ? std::vector<std::string>{"Z"} : names[format.channels], 4};
    case E::unorm8:
    case E::srgb8:
    case E::uint8: return {Imf::UINT, names[format.channels], 1};
    case E::unorm16:
    case E::uint16: return {Imf::UINT, format.is_depth ? std::vector<std::string>{"Z"} : names[format.channels], 2};
    case E::uint32: return {Imf::UINT, names[format.channels], 4};
    case E::packed_a2b10g10r10:
    case E::packed_b10g11r11: return {Imf::UINT, {"packed"}, 0};
    case E::depth32_stencil8: return aspect == 0 ? Layout{Imf::FLOAT, {"Z"}, 4} : Layout{Imf::UINT, {"S"}, 1};
  }
  return {Imf::UINT, {}, 0};
}

std::string part_name(uint32_t aspect, uint32_t mip, uint32_t layer) {
  return "a" + std::to_string(aspect) + ".m" + std::to_string(mip) + ".l" + std::to_string(layer);
}

void init_threads() {
  static std::once_flag once;
  std::call_once(once, [] { Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency()))); });
}

Imf::Compression exr_compression(ExrCompression c) {
  switch (c) {
    case ExrCompression::none: return Imf::NO_COMPRESSION;
    case ExrCompression::rle: return Imf::RLE_COMPRESSION;
    case ExrCompression::zip: return Imf::ZIP_COMPRESSION;
    case ExrCompression::piz: return Imf::PIZ_COMPRESSION;
  }
  return Imf::ZIP_COMPRESSION;
}

// One subresource as EXR samples: HALF/FLOAT keep their bits; integer codes widen to uint32.
struct Samples {
  std::vector<uint8_t> data;
  size_t sample_bytes;
};

Samples to_samples(const Layout& layout, const uint8_t* raw, uint64_t texels, uint32_t channels) {
  Samples s;
  s.sample_bytes = layout.type == Imf::HALF ? 2 : 4;
  const uint32_t count = layout.raw_bytes_per_channel == 0 ? 1 : channels;
  s.data.resize(texels * count * s.sample_bytes);
  if (layout.type != Imf::UINT || layout.raw_bytes_per_channel == 4 || layout.raw_bytes_per_channel == 0) {
    std::memcpy(s.data.data(), raw, s.data.size());
    return s;
  }
  for (uint64_t i = 0; i < texels * count; ++i) {
    uint32_t value = 0;
    std::memcpy(&value, raw + i * layout.raw_bytes_per_channel, layout.raw_bytes_per_channel);
    std::memcpy(s.data.data() + i * 4, &value, 4);
  }
  return s;
}

void from_samples(const Layout& layout, const Samples& s, uint8_t* raw, uint64_t texels, uint32_t channels) {
  const uint32_t count = layout.raw_bytes_per_channel == 0 ? 1 : channels;
  if (layout.type != Imf::UINT || layout.raw_bytes_per_channel == 4 || layout.raw_bytes_per_channel == 0) {
    std::memcpy(raw, s.data.data(), texels * count * s.sample_bytes);
    return;
  }
  for (uint64_t i = 0; i < texels * count; ++i) {
    uint32_t value;
    std::memcpy(&value, s.data.data() + i * 4, 4);
    std::memcpy(raw + i * layout.raw_bytes_per_channel, &value, layout.raw_bytes_per_channel);
  }
}

Imf::FrameBuffer frame_buffer(const Layout& layout, Samples& s, uint32_t width, uint32_t channels_per_texel,
                              int min_x, int min_y) {
  Imf::FrameBuffer fb;
  const size_t stride_x = s.sample_bytes * layout.channels.size();
  const size_t stride_y = stride_x * width;
  (void)channels_per_texel;
  // OpenEXR addresses samples relative to the data window's origin.
  char* base = reinterpret_cast<char*>(s.data.data()) - min_x * stride_x - min_y * stride_y;
  for (size_t c = 0; c < layout.channels.size(); ++c)
    fb.insert(layout.channels[c], Imf::Slice(layout.type, base + c * s.sample_bytes, stride_x, stride_y));
  return fb;
}

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& problem) {
  throw CaptureError(file.string() + ": " + problem);
}

}  // namespace

std::string image_blob_extension() { return "exr"; }
std::string buffer_blob_extension() { return "bin.zst"; }

void write_image_blob(const std::filesystem::path& file, const FormatInfo& format, const ImageExtent& extent,
                      std::span<const uint8_t> raw, ExrCompression compression) {
  init_threads();
  if (raw.size() != raw_image_bytes(format, extent))
    throw std::logic_error("write_image_blob: raw size does not match the format and extent");
  std::vector<Imf::Header> headers;
  for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect)
    for (uint32_t mip = 0; mip < extent.mips; ++mip)
      for (uint32_t layer = 0; layer < extent.layers; ++layer) {
        const Layout layout = layout_of(format, aspect);
        // 3D slices stack vertically in one part.
        Imf::Header header(int(mip_size(extent.width, mip)), int(mip_size(extent.height, mip) * mip_size(extent.depth, mip)));
        header.compression() = exr_compression(compression);
        header.setName(part_name(aspect, mip, layer));
        header.setType(Imf::SCANLINEIMAGE);
        for (const std::string& c : layout.channels) header.channels().insert(c, Imf::Channel(layout.type));
        header.insert("nightcap.format", Imf::StringAttribute(std::string(format.name)));
        header.insert("nightcap.extent", Imf::StringAttribute(std::to_string(extent.width) + "x" + std::to_string(extent.height) + "x" +
                                                              std::to_string(extent.depth) + " mips " + std::to_string(extent.mips) +
                                                              " layers " + std::to_string(extent.layers)));
        headers.push_back(header);
      }
  try {
    Imf::MultiPartOutputFile out(file.c_str(), headers.data(), int(headers.size()));
    int part = 0;
    for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect)
      for (uint32_t mip = 0; mip < extent.mips; ++mip)
        for (uint32_t layer = 0; layer < extent.layers; ++layer, ++part) {
          const Layout layout = layout_of(format, aspect);
          const uint32_t w = mip_size(extent.width, mip), h = mip_size(extent.height, mip) * mip_size(extent.depth, mip);
          const uint8_t* data = raw.data() + raw_subresource_offset(format, extent, aspect, mip, layer);
          Samples samples = to_samples(layout, data, uint64_t(w) * h, aspect_channels(format, aspect));
          Imf::OutputPart output(out, part);
          output.setFrameBuffer(frame_buffer(layout, samples, w, aspect_channels(format, aspect), 0, 0));
          output.writePixels(int(h));
        }
  } catch (const std::exception& e) {
    fail(file, std::string("cannot write OpenEXR: ") + e.what());
  }
}

std::vector<uint8_t> read_image_blob(const std::filesystem::path& file, const FormatInfo& format,
                                     const ImageExtent& extent) {
  init_threads();
  std::vector<uint8_t> raw(raw_image_bytes(format, extent));
  try {
    Imf::MultiPartInputFile in(file.c_str());
    const uint32_t expected_parts = aspect_count(format) * extent.mips * extent.layers;
    if (uint32_t(in.parts()) != expected_parts)
      fail(file, "has " + std::to_string(in.parts()) + " parts, expected " + std::to_string(expected_parts));
    int part = 0;
    for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect)
      for (uint32_t mip = 0; mip < extent.mips; ++mip)
        for (uint32_t layer = 0; layer < extent.layers; ++layer, ++part) {
          const Imf::Header& header = in.header(part);
          const auto* stored = header.findTypedAttribute<Imf::StringAttribute>("nightcap.format");
          if (!stored || stored->value() != format.name)
            fail(file, "part " + std::to_string(part) + " is not " + std::string(format.name));
          const Layout layout = layout_of(format, aspect);
          const uint32_t w = mip_size(extent.width, mip), h = mip_size(extent.height, mip) * mip_size(extent.depth, mip);
          const Imath::Box2i window = header.dataWindow();
          if (uint32_t(window.max.x - window.min.x + 1) != w || uint32_t(window.max.y - window.min.y + 1) != h)
            fail(file, "part " + std::to_string(part) + " has the wrong size for mip " + std::to_string(mip));
          for (const std::string& c : layout.channels) {
            const Imf::Channel* channel = header.channels().findChannel(c);
            if (!channel || channel->type != layout.type || channel->xSampling != 1 || channel->ySampling != 1)
              fail(file, "part " + std::to_string(part) + " lacks channel " + c + " of the expected type");
          }
          Samples samples;
          samples.sample_bytes = layout.type == Imf::HALF ? 2 : 4;
          samples.data.resize(uint64_t(w) * h * layout.channels.size() * samples.sample_bytes);
          Imf::InputPart input(in, part);
          input.setFrameBuffer(frame_buffer(layout, samples, w, aspect_channels(format, aspect), window.min.x, window.min.y));
          input.readPixels(window.min.y, window.max.y);
          from_samples(layout, samples, raw.data() + raw_subresource_offset(format, extent, aspect, mip, layer),
                       uint64_t(w) * h, aspect_channels(format, aspect));
        }
  } catch (const CaptureError&) {
    throw;
  } catch (const std::exception& e) {
    fail(file, std::string("unreadable OpenEXR: ") + e.what());
  }
  return raw;
}

void write_buffer_blob(const std::filesystem::path& file, std::span<const uint8_t> raw, int zstd_level) {
  std::vector<uint8_t> compressed(ZSTD_compressBound(raw.size()));
  const size_t size = ZSTD_compress(compressed.data(), compressed.size(), raw.data(), raw.size(), zstd_level);
  if (ZSTD_isError(size)) fail(file, std::string("zstd: ") + ZSTD_getErrorName(size));
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(compressed.data()), std::streamsize(size));
  if (!out) fail(file, "cannot write");
}

std::vector<uint8_t> read_buffer_blob(const std::filesystem::path& file, uint64_t expected_size) {
  if (expected_size > (uint64_t(4) << 30)) fail(file, "buffer larger than 4 GiB");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open");
  std::vector<uint8_t> compressed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const unsigned long long content = ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN) fail(file, "not a zstd frame");
  if (content != expected_size)
    fail(file, "holds " + std::to_string(content) + " bytes, expected " + std::to_string(expected_size));
  std::vector<uint8_t> raw(expected_size);
  const size_t size = ZSTD_decompress(raw.data(), raw.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size) || size != expected_size) fail(file, "corrupt zstd data");
  return raw;
}

}  // namespace nightcap
