#include "inspect/export.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <half.h>

#include <optional>
#include <thread>
#include <vector>

#include "inspect/decode.h"

namespace nightcap {

namespace {

constexpr uint64_t kTexelsWorthAThread = 1u << 16;

// An uncompressed file is written a scanline at a time, and OpenEXR hands every line buffer to
// its global pool whatever OutputFile's own thread count: a task per line costs more than the
// copy it does (an export of five 1280x720 targets took 0.40 s of CPU with the pool, 0.24 s
// without). While one of these lives, the pool has no threads and the lines are written here.
class LinesOnThisThread {
 public:
  LinesOnThisThread() : pool_threads_(Imf::globalThreadCount()) {
    if (pool_threads_ > 0) Imf::setGlobalThreadCount(0);
  }
  ~LinesOnThisThread() {
    if (pool_threads_ > 0) Imf::setGlobalThreadCount(pool_threads_);
  }
  LinesOnThisThread(const LinesOnThisThread&) = delete;
  LinesOnThisThread& operator=(const LinesOnThisThread&) = delete;

 private:
  int pool_threads_;
};

// Decodes every channel of one subimage into planes of `Channel` (float or half) and writes
// them: decoding straight to the stored type keeps one copy of the image in memory.
template <typename Channel>
void write_exr(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
               const Subimage& subimage, Imf::PixelType type, Imf::Compression compression) {
  const FormatInfo format = *format_info(record.format);
  const uint32_t mip = subimage.mip;
  const uint32_t width = mip_size(record.extent.width, mip), height = mip_size(record.extent.height, mip);
  const uint64_t texels = uint64_t(width) * height;
  std::vector<std::string> names;
  std::vector<std::vector<Channel>> planes;
  for (uint32_t aspect = 0; aspect < aspect_count(format); ++aspect) {
    const uint64_t slice_bytes = texels * aspect_texel_bytes(format, aspect);
    const std::span<const uint8_t> plane = raw.subspan(
        raw_subresource_offset(format, record.extent, aspect, mip, subimage.layer) + subimage.slice * slice_bytes,
        slice_bytes);
    const uint32_t channels = aspect_channels(format, aspect);
    const size_t first = planes.size();
    for (uint32_t c = 0; c < channels; ++c) {
      names.push_back(format.is_depth ? (aspect == 0 ? "Z" : "S") : std::string(1, "RGBA"[c]));
      planes.emplace_back(texels);
    }
    auto decode = [&](uint64_t begin, uint64_t end) {
      for (uint64_t i = begin; i < end; ++i) {
        float values[4] = {};
        decode_texel(format, aspect, plane, i, values);
        for (uint32_t c = 0; c < channels; ++c) planes[first + c][i] = Channel(values[c]);
      }
    };
    // Decoding is most of an export's time; a second thread halves it for full-size targets.
    if (texels >= kTexelsWorthAThread && std::thread::hardware_concurrency() > 1) {
      std::thread second_half(decode, texels / 2, texels);
      decode(0, texels / 2);
      second_half.join();
    } else {
      decode(0, texels);
    }
  }
  try {
    Imf::Header header(static_cast<int>(width), static_cast<int>(height));
    header.compression() = compression;
    Imf::FrameBuffer buffer;
    for (size_t c = 0; c < names.size(); ++c) {
      header.channels().insert(names[c], Imf::Channel(type));
      buffer.insert(names[c], Imf::Slice(type, reinterpret_cast<char*>(planes[c].data()), sizeof(Channel),
                                         sizeof(Channel) * width));
    }
    std::optional<LinesOnThisThread> inline_lines;
    if (compression == Imf::NO_COMPRESSION) inline_lines.emplace();
    Imf::OutputFile out(file.c_str(), header, inline_lines ? 0 : Imf::globalThreadCount());
    out.setFrameBuffer(buffer);
    out.writePixels(int(height));
  } catch (const std::exception& e) {
    throw InspectError(file.string() + ": cannot write: " + e.what());
  }
}

}  // namespace

void write_values_exr(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
                      const Subimage& subimage, const ValuesExr& options) {
  check_subimage(record, subimage);
  const Imf::Compression compression = options.compressed ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
  if (options.half)
    write_exr<Imath::half>(file, record, raw, subimage, Imf::HALF, compression);
  else
    write_exr<float>(file, record, raw, subimage, Imf::FLOAT, compression);
}

}  // namespace nightcap
