// Every kind of blob is checked against its hash when it is read: a resource (whose damaged file
// still decodes), a shader's SPIR-V and its GLSL source. Opening the capture reads none of them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "captures/capture.h"
#include "passes/core/hash.h"
#include "tests/unit/scratch_folder.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

struct Written {
  fs::path folder;
  ResourceRecord buffer;
  ShaderRecord shader;
};

Written write_capture(const fs::path& folder) {
  CaptureWriter writer(folder, false, {});
  Written w{folder, {}, {}};
  w.buffer.resource = "probe.buffer";
  w.buffer.buffer_size = 64;
  auto raw = std::make_shared<std::vector<uint8_t>>(64);
  for (size_t i = 0; i < raw->size(); ++i) (*raw)[i] = uint8_t(i * 7);
  writer.add_resource(w.buffer, raw);
  const std::vector<uint32_t> spirv = {0x07230203, 0x00010000, 0, 1, 0};
  w.shader = writer.add_shader("probe/probe.comp", spirv, "#version 450\nvoid main() {}\n");
  CaptureManifest manifest;
  manifest.device = manifest.settings = manifest.scene = nlohmann::json::object();
  FrameRecord frame;
  frame.width = frame.height = 8;
  PassRecord pass;
  pass.name = "probe";
  pass.ran = true;
  pass.shaders.push_back(w.shader);
  pass.inputs.push_back(w.buffer);
  frame.passes.push_back(pass);
  manifest.frames.push_back(frame);
  writer.commit(manifest);
  return w;
}

// Same size as the file it replaces, so that nothing but the hash can tell.
void overwrite(const fs::path& file, char fill) {
  const auto size = fs::file_size(file);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << std::string(size, fill);
}

template <typename Load>
void expect_hash_mismatch(Load load, const std::string& blob, const std::string& hash) {
  try {
    load();
    ADD_FAILURE() << blob << " was read although it does not match its hash";
  } catch (const CaptureError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(blob), std::string::npos) << message;
    EXPECT_NE(message.find("does not match its hash " + hash), std::string::npos) << message;
  }
}

TEST(CaptureBlobs, EachIsReadIntactAndOpeningReadsNone) {
  const ScratchFolder scratch("blobs-test");
  const Written w = write_capture(scratch.path / "capture");
  const Capture capture = Capture::open(w.folder);
  const PassRecord& pass = capture.frame(0).passes.at(0);
  EXPECT_EQ(capture.load(pass.inputs.at(0)).size(), 64u);
  EXPECT_EQ(capture.load_shader(pass.shaders.at(0)).at(0), 0x07230203u);
  EXPECT_EQ(capture.load_shader_source(pass.shaders.at(0)), "#version 450\nvoid main() {}\n");

  for (const auto& entry : fs::directory_iterator(w.folder / "blobs")) overwrite(entry.path(), 'x');
  const Capture damaged = Capture::open(w.folder);
  EXPECT_EQ(to_json(damaged.manifest()), to_json(capture.manifest()));
}

TEST(CaptureBlobs, AResourceWhoseFileDecodesToOtherBytesIsRefused) {
  const ScratchFolder scratch("blobs-test");
  const Written w = write_capture(scratch.path / "capture");
  write_buffer_blob(w.folder / w.buffer.blob, std::vector<uint8_t>(64, 0x5a), 3);
  const Capture capture = Capture::open(w.folder);
  expect_hash_mismatch([&] { capture.load(capture.frame(0).passes[0].inputs[0]); }, w.buffer.blob, w.buffer.hash);
}

TEST(CaptureBlobs, ADamagedShaderOrShaderSourceIsRefused) {
  const ScratchFolder scratch("blobs-test");
  const Written w = write_capture(scratch.path / "capture");
  overwrite(w.folder / w.shader.blob, 'x');
  overwrite(w.folder / w.shader.source_blob, 'x');
  const Capture capture = Capture::open(w.folder);
  const ShaderRecord& shader = capture.frame(0).passes[0].shaders[0];
  expect_hash_mismatch([&] { capture.load_shader(shader); }, w.shader.blob, w.shader.hash);
  expect_hash_mismatch([&] { capture.load_shader_source(shader); }, w.shader.source_blob, w.shader.source_hash);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
