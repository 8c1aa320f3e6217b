#include "captures/exr_headers.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <string_view>

#include "captures/blob_codec.h"

namespace nightcap {

namespace {

constexpr uint32_t kMagic = 20000630;
constexpr uint32_t kTiled = 0x200, kLongNames = 0x400, kDeep = 0x800, kMultipart = 0x1000;

// What write_image_blob writes: attribute name -> type.
const std::map<std::string_view, std::string_view> kAttributes = {
    {"channels", "chlist"},
    {"chunkCount", "int"},
    {"compression", "compression"},
    {"dataWindow", "box2i"},
    {"displayWindow", "box2i"},
    {"lineOrder", "lineOrder"},
    {"name", "string"},
    {"type", "string"},
    {"pixelAspectRatio", "float"},
    {"screenWindowCenter", "v2f"},
    {"screenWindowWidth", "float"},
    {"nightcap.format", "string"},
    {"nightcap.width", "int"},
    {"nightcap.height", "int"},
    {"nightcap.depth", "int"},
    {"nightcap.mips", "int"},
    {"nightcap.layers", "int"},
};
const std::map<std::string_view, int32_t> kFixedSizes = {{"int", 4},       {"float", 4},  {"compression", 1},
                                                         {"lineOrder", 1}, {"box2i", 16}, {"v2f", 8}};
constexpr int32_t kMaxString = 256;
constexpr int32_t kChannelTail = 16;  // pixel type, pLinear, 3 reserved bytes, x and y sampling

class HeaderReader {
 public:
  explicit HeaderReader(const std::filesystem::path& file) : file_(file), in_(file, std::ios::binary) {
    std::error_code error;
    size_ = std::filesystem::file_size(file, error);
    if (!in_ || error) fail("cannot open");
  }

  [[noreturn]] void fail(const std::string& problem) const { throw CaptureError(file_.string() + ": " + problem); }

  template <class T>
  T value(const char* what) {
    T v;
    if (!in_.read(reinterpret_cast<char*>(&v), sizeof v)) fail(std::string("ends inside ") + what);
    return v;
  }

  // A null-terminated name of at most `longest` characters.
  std::string name(size_t longest, const char* what) {
    std::string text;
    if (!std::getline(in_, text, '\0')) fail(std::string("ends inside ") + what);
    if (text.size() > longest) fail(std::string("has an OpenEXR ") + what + " longer than " + std::to_string(longest));
    return text;
  }

  uint64_t left() { return size_ - uint64_t(in_.tellg()); }
  void skip(int32_t bytes) { in_.seekg(bytes, std::ios::cur); }

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

// Walks a channel list of `size` bytes, which must end exactly there.
void check_channel_list(HeaderReader& reader, int32_t size, size_t longest_name) {
  int64_t consumed = 0;
  for (;;) {
    const std::string channel = reader.name(longest_name, "channel name");
    consumed += int64_t(channel.size()) + 1;
    if (channel.empty()) break;
    if (consumed + kChannelTail > size) reader.fail("has a channel list longer than its stated size");
    reader.skip(kChannelTail);
    consumed += kChannelTail;
  }
  if (consumed != size) reader.fail("has a channel list that does not end at its stated size");
}

}  // namespace

void check_exr_headers(const std::filesystem::path& file, const std::vector<ExpectedPart>& parts) {
  HeaderReader reader(file);
  if (reader.value<uint32_t>("the OpenEXR magic number") != kMagic) reader.fail("is not OpenEXR");
  const uint32_t version = reader.value<uint32_t>("the OpenEXR version");
  if ((version & 0xff) != 2) reader.fail("has OpenEXR version " + std::to_string(version & 0xff) + ", not 2");
  if (version & (kTiled | kDeep)) reader.fail("is not a scanline image");
  if (version & ~uint32_t(0xff | kLongNames | kMultipart)) reader.fail("has unknown OpenEXR flags");
  const bool multipart = version & kMultipart;
  if (!multipart && parts.size() != 1) reader.fail("has 1 part, expected " + std::to_string(parts.size()));
  const size_t longest_name = (version & kLongNames) ? 255 : 31;

  for (size_t part = 0;; ++part) {
    std::map<std::string, bool> seen;
    int32_t data_rows = -1, chunk_count = -1;
    for (;;) {
      const std::string attribute = reader.name(longest_name, "attribute name");
      if (attribute.empty()) break;
      const auto known = kAttributes.find(attribute);
      if (known == kAttributes.end()) reader.fail("has an OpenEXR attribute nightcap does not write: " + attribute);
      if (seen[attribute]) reader.fail("has attribute " + attribute + " twice");
      seen[attribute] = true;
      if (part >= parts.size()) reader.fail("has more than the " + std::to_string(parts.size()) + " parts expected");
      const std::string type = reader.name(longest_name, "attribute type");
      if (type != known->second) reader.fail("has attribute " + attribute + " of type " + type);
      const int32_t size = reader.value<int32_t>("an attribute size");
      if (size < 0 || uint64_t(size) > reader.left())
        reader.fail("has attribute " + attribute + " past the end of the file");
      if (const auto fixed = kFixedSizes.find(type); fixed != kFixedSizes.end()) {
        if (size != fixed->second) reader.fail("has attribute " + attribute + " of the wrong size");
      } else if (type == "string" && size > kMaxString) {
        reader.fail("has a string attribute " + attribute + " longer than " + std::to_string(kMaxString));
      }
      if (type == "chlist") {
        check_channel_list(reader, size, longest_name);
      } else if (attribute == "dataWindow") {
        const int32_t min_x = reader.value<int32_t>("dataWindow"), min_y = reader.value<int32_t>("dataWindow");
        const int32_t max_x = reader.value<int32_t>("dataWindow"), max_y = reader.value<int32_t>("dataWindow");
        if (int64_t(max_x) - min_x + 1 != parts[part].width || int64_t(max_y) - min_y + 1 != parts[part].rows)
          reader.fail("part " + std::to_string(part) + " has a data window of the wrong size");
        data_rows = parts[part].rows;
      } else if (attribute == "chunkCount") {
        chunk_count = reader.value<int32_t>("chunkCount");
      } else {
        reader.skip(size);
      }
    }
    if (seen.empty()) {
      // An empty header ends a multi-part file's list; a single-part file has no such header.
      if (part == 0) reader.fail("has no OpenEXR header");
      if (part != parts.size())
        reader.fail("has " + std::to_string(part) + " parts, expected " + std::to_string(parts.size()));
      return;
    }
    if (data_rows < 0) reader.fail("part " + std::to_string(part) + " has no data window");
    if (multipart && (chunk_count < 1 || chunk_count > data_rows))
      reader.fail("part " + std::to_string(part) + " has a chunk count that does not fit its rows");
    if (!multipart) return;
  }
}

}  // namespace nightcap
