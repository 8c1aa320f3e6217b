// The golden store: one copy of each blob across its goldens, goldens read through the store and
// never outside it, and updates that change nothing unless every blob they copy is intact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <set>

#include "captures/golden_store.h"
#include "passes/core/hash.h"
#include "tests/unit/scratch_folder.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

std::vector<uint8_t> bytes_of(uint8_t seed) {
  std::vector<uint8_t> raw(64);
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = uint8_t(seed + i * 7);
  return raw;
}

// A capture of one pass reading a buffer per seed, with the same shader in every capture.
fs::path write_capture(const fs::path& folder, const std::vector<uint8_t>& seeds) {
  CaptureWriter writer(folder, false, {});
  CaptureManifest manifest;
  manifest.device = manifest.settings = manifest.scene = json::object();
  FrameRecord frame;
  frame.width = frame.height = 8;
  PassRecord pass;
  pass.name = "probe";
  pass.ran = true;
  const std::vector<uint32_t> spirv = {0x07230203, 0x00010000, 0, 1, 0};
  pass.shaders.push_back(writer.add_shader("probe/probe.comp", spirv, "#version 450\nvoid main() {}\n"));
  for (uint8_t seed : seeds) {
    ResourceRecord buffer;
    buffer.resource = "probe.buffer" + std::to_string(seed);
    buffer.buffer_size = 64;
    writer.add_resource(buffer, std::make_shared<std::vector<uint8_t>>(bytes_of(seed)));
    pass.inputs.push_back(buffer);
  }
  frame.passes.push_back(pass);
  manifest.frames.push_back(frame);
  writer.commit(manifest);
  return folder;
}

std::set<std::string> files_in(const fs::path& folder) {
  std::set<std::string> names;
  if (!fs::exists(folder)) return names;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    names.insert(fs::relative(entry.path(), folder).string());
  return names;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <typename Call>
std::string capture_error(Call call) {
  try {
    call();
  } catch (const CaptureError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no CaptureError";
  return "";
}

TEST(GoldenStore, GoldensFromCapturesSharingBlobsKeepOneCopyOfEach) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  const fs::path a = write_capture(scratch.path / "a", {1, 2}), b = write_capture(scratch.path / "b", {1, 3});
  ASSERT_EQ(files_in(a / "blobs").size(), 4u) << "two buffers, the SPIR-V and its source";

  const GoldenUpdate first = GoldenStore::update(store, a, "a");
  EXPECT_EQ(first.blobs_copied, 4u);
  EXPECT_EQ(first.blobs_shared, 0u);
  const GoldenUpdate second = GoldenStore::update(store, b, "b");
  EXPECT_EQ(second.blobs_copied, 1u) << "buffer 3";
  EXPECT_EQ(second.blobs_shared, 3u) << "buffer 1 and the shader's two blobs";
  EXPECT_EQ(files_in(store / "blobs").size(), 5u);
  EXPECT_EQ(files_in(store / "goldens"), (std::set<std::string>{"a", "a/manifest.json", "b", "b/manifest.json"}));
  EXPECT_TRUE(files_in(store / "tmp").empty());

  const GoldenStore opened = GoldenStore::open(store);
  for (const auto& [name, seeds] :
       std::vector<std::pair<std::string, std::vector<uint8_t>>>{{"a", {1, 2}}, {"b", {1, 3}}}) {
    const Capture golden = opened.golden(name);
    EXPECT_EQ(golden.blob_root(), fs::canonical(store));
    const PassRecord& pass = golden.frame(0).passes.at(0);
    for (size_t i = 0; i < seeds.size(); ++i) EXPECT_EQ(golden.load(pass.inputs.at(i)), bytes_of(seeds[i]));
    EXPECT_EQ(golden.load_shader_source(pass.shaders.at(0)), "#version 450\nvoid main() {}\n");
  }
  const std::vector<GoldenInfo> list = opened.list();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].name, "a");
  EXPECT_EQ(list[0].source, fs::absolute(a).lexically_normal().string());
  EXPECT_EQ(list[1].frames, 1u);
  EXPECT_EQ(list[1].passes, 1u);
}

TEST(GoldenStore, AnUpdateReplacesTheGoldenOfThatName) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "g");
  GoldenStore::update(store, write_capture(scratch.path / "b", {2}), "g");
  const GoldenStore opened = GoldenStore::open(store);
  ASSERT_EQ(opened.list().size(), 1u);
  EXPECT_EQ(opened.list()[0].source, fs::absolute(scratch.path / "b").lexically_normal().string());
  EXPECT_EQ(opened.golden("g").load(opened.golden("g").frame(0).passes[0].inputs[0]), bytes_of(2));
  EXPECT_TRUE(files_in(store / "tmp").empty());
}

TEST(GoldenStore, ABlobLinkedOutOfTheStoreIsRefused) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "g");
  const Capture golden = GoldenStore::open(store).golden("g");
  const ResourceRecord& buffer = golden.frame(0).passes[0].inputs[0];
  // Outside the store, with the right content: only where it lives is wrong.
  fs::copy_file(store / buffer.blob, scratch.path / "outside.bin.zst");
  fs::remove(store / buffer.blob);
  fs::create_symlink(scratch.path / "outside.bin.zst", store / buffer.blob);
  const std::string message = capture_error([&] { golden.load(buffer); });
  EXPECT_NE(message.find("leaves the store"), std::string::npos) << message;

  // The whole blobs/ folder as a link out of the store.
  fs::rename(store / "blobs", scratch.path / "blobs-elsewhere");
  fs::create_symlink(scratch.path / "blobs-elsewhere", store / "blobs");
  const std::string folder_message = capture_error([&] { golden.load_shader(golden.frame(0).passes[0].shaders[0]); });
  EXPECT_NE(folder_message.find("leaves the store"), std::string::npos) << folder_message;
}

TEST(GoldenStore, ABlobPathWithDotDotIsRefused) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "g");
  const fs::path manifest = store / "goldens" / "g" / "manifest.json";
  json j = json::parse(read_text(manifest));
  json& input = j["frames"][0]["passes"][0]["inputs"][0];
  input["blob"] = "blobs/../../" + input["blob"].get<std::string>().substr(6);
  std::ofstream(manifest, std::ios::trunc) << j.dump();
  const std::string message = capture_error([&] { GoldenStore::open(store).golden("g"); });
  EXPECT_NE(message.find(manifest.string()), std::string::npos) << message;
  EXPECT_NE(message.find("leaves blobs/"), std::string::npos) << message;
}

TEST(GoldenStore, AStoreManifestOutsideAStoreIsRefused) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "g");
  fs::remove(store / kStoreMarker);
  const fs::path manifest = store / "goldens" / "g" / "manifest.json";
  const std::string message = capture_error([&] { Capture::open(store / "goldens" / "g"); });
  EXPECT_NE(message.find(manifest.string()), std::string::npos) << message;
  EXPECT_NE(message.find(std::string("has no ") + kStoreMarker), std::string::npos) << message;
  EXPECT_NE(capture_error([&] { GoldenStore::open(store); }).find("not a golden store"), std::string::npos);

  // A golden's folder copied out of its store: its blob paths would name nothing there.
  GoldenStore::update(scratch.path / "store2", scratch.path / "a", "g");
  fs::copy(scratch.path / "store2" / "goldens" / "g", scratch.path / "loose");
  const std::string loose = capture_error([&] { Capture::open(scratch.path / "loose"); });
  EXPECT_NE(loose.find("not in a store's goldens/"), std::string::npos) << loose;
}

TEST(GoldenStore, AStoreOfAnotherVersionIsRefused) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "g");
  std::ofstream(store / kStoreMarker, std::ios::trunc) << R"({"format": "nightcap-store", "version": 99})";
  const std::string message = capture_error([&] { GoldenStore::open(store); });
  EXPECT_NE(message.find("store version 99"), std::string::npos) << message;
}

TEST(GoldenStore, AHostileNameWritesNothing) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  const fs::path a = write_capture(scratch.path / "a", {1});
  const std::set<std::string> before = files_in(scratch.path);
  for (const std::string name : {"../x", "a/b", "", ".", "..", "a\\b", "a b"}) {
    const std::string message = capture_error([&] { GoldenStore::update(store, a, name); });
    EXPECT_NE(message.find("not a safe file name"), std::string::npos) << name << ": " << message;
  }
  EXPECT_EQ(files_in(scratch.path), before) << "no store, nothing beside the capture";
}

// A damaged blob of the capture being recorded: the update fails naming it, and the store keeps
// what it had, with no golden of the new name and nothing staged.
class DamagedSource : public ::testing::TestWithParam<std::string> {};

TEST_P(DamagedSource, LeavesTheStoreAsItWas) {
  const ScratchFolder scratch("golden-store-test");
  const fs::path store = scratch.path / "store";
  GoldenStore::update(store, write_capture(scratch.path / "a", {1}), "kept");
  const fs::path b = write_capture(scratch.path / "b", {1, 2, 3});
  const ResourceRecord damaged = Capture::open(b).frame(0).passes[0].inputs[2];
  const fs::path file = b / damaged.blob;
  if (GetParam() == "truncated")
    fs::resize_file(file, fs::file_size(file) / 2);
  else
    write_buffer_blob(file, std::vector<uint8_t>(64, 0x5a), 3);  // decodes, to other bytes
  const std::set<std::string> before = files_in(store);
  const std::string kept_manifest = read_text(store / "goldens" / "kept" / "manifest.json");

  for (const std::string name : {"new", "kept"}) {
    const std::string message = capture_error([&] { GoldenStore::update(store, b, name); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_EQ(files_in(store), before) << name;
  }
  EXPECT_EQ(read_text(store / "goldens" / "kept" / "manifest.json"), kept_manifest);

  // A store the failed update would have created is not left behind.
  const std::string message = capture_error([&] { GoldenStore::update(scratch.path / "fresh", b, "new"); });
  EXPECT_FALSE(fs::exists(scratch.path / "fresh")) << message;
}

INSTANTIATE_TEST_SUITE_P(GoldenStore, DamagedSource, ::testing::Values("truncated", "corrupt"));

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
