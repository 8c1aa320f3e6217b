// The capture writer encodes blobs in the background: what it records must be on disk when the
// capture commits, equal bytes in two formats must stay two readable blobs, and a blob that
// fails to encode must fail the commit rather than leave a capture missing it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "captures/capture.h"
#include "passes/gbuffer/kinds.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("nightcap-writer-" + std::to_string(::getpid()));
  TempDir() { fs::remove_all(path); }
  ~TempDir() { fs::remove_all(path); }
};

ResourceRecord image(const std::string& name, VkFormat format, ResourceKind kind) {
  ResourceRecord r;
  r.resource = name;
  r.kind = kind;
  r.is_buffer = false;
  r.format = format;
  r.extent.width = r.extent.height = 2;
  return r;
}

CaptureManifest manifest_with(std::vector<ResourceRecord> outputs) {
  CaptureManifest manifest;
  manifest.device = manifest.settings = manifest.scene = nlohmann::json::object();
  FrameRecord frame;
  frame.width = frame.height = 2;
  PassRecord pass;
  pass.name = "test.pass";
  pass.ran = true;
  pass.outputs = std::move(outputs);
  frame.passes.push_back(pass);
  manifest.frames.push_back(frame);
  return manifest;
}

TEST(CaptureWriter, EqualBytesInTwoFormatsAreTwoReadableBlobs) {
  TempDir dir;
  // 16 bytes: a 2x2 R32_SFLOAT image and a 2x2 RGBA8 one with the same raw bytes.
  auto bytes = std::make_shared<const std::vector<uint8_t>>(
      std::vector<uint8_t>{0, 0, 128, 63, 0, 0, 0, 64, 0, 0, 64, 64, 0, 0, 128, 64});
  ResourceRecord depth = image("depth.linear", VK_FORMAT_R32_SFLOAT, kinds::linear_depth);
  ResourceRecord colour = image("gbuffer.material", VK_FORMAT_R8G8B8A8_UNORM, kinds::material);
  {
    CaptureWriter writer(dir.path / "cap", false, {});
    writer.add_resource(depth, bytes);
    writer.add_resource(colour, bytes);
    writer.commit(manifest_with({depth, colour}));
  }
  EXPECT_EQ(depth.hash, colour.hash);
  EXPECT_NE(depth.blob, colour.blob);
  const Capture capture = Capture::open(dir.path / "cap");
  for (const ResourceRecord& r : capture.frame(0).passes[0].outputs) EXPECT_EQ(capture.load(r), *bytes) << r.resource;
}

TEST(CaptureWriter, EveryKindAndForcedCodecRoundTrips) {
  TempDir dir;
  std::vector<uint8_t> raw(2 * 2 * 8);
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = uint8_t(i * 37 + 11);
  auto bytes = std::make_shared<const std::vector<uint8_t>>(raw);
  for (std::optional<ImageEncoding> forced : {std::optional<ImageEncoding>{}, image_encoding_by_name("pxr24_1"),
                                              image_encoding_by_name("zips9"), image_encoding_by_name("rle")}) {
    SCOPED_TRACE(forced ? image_encoding_name(*forced) : "auto");
    std::vector<ResourceRecord> records;
    const fs::path folder = dir.path / (forced ? image_encoding_name(*forced) : "auto");
    CaptureWriter writer(folder, false, {forced, 3, 2});
    for (const ResourceKind kind : registered_kinds()) {
      records.push_back(image("r." + std::string(kind.name()), VK_FORMAT_R32G32_SFLOAT, kind));
      writer.add_resource(records.back(), bytes);
    }
    writer.commit(manifest_with(records));
    const Capture capture = Capture::open(folder);
    for (const ResourceRecord& r : capture.frame(0).passes[0].outputs) EXPECT_EQ(capture.load(r), raw) << r.resource;
  }
}

TEST(CaptureWriter, ABlobThatCannotBeWrittenFailsTheCommit) {
  TempDir dir;
  ResourceRecord colour = image("final.ldr", VK_FORMAT_R8G8B8A8_SRGB, kinds::colour);
  CaptureWriter writer(dir.path / "cap", false, {});
  // The blobs folder vanishes under the writer: the queued encode cannot write its file.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir.path))
    if (entry.path().filename().string().rfind("cap.tmp-", 0) == 0) fs::remove_all(entry.path() / "blobs");
  writer.add_resource(colour, std::make_shared<const std::vector<uint8_t>>(16, uint8_t(7)));
  EXPECT_THROW(writer.commit(manifest_with({colour})), CaptureError);
  EXPECT_FALSE(fs::exists(dir.path / "cap"));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
