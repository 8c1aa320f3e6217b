// Every input that once crashed a fuzzing harness (tests/fuzz/corpus, named for what it does)
// gets the clear error it should have got: the fix is checked in this build too, not only in the
// instrumented one that runs the corpus.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>

#include "captures/blob_codec.h"
#include "captures/capture.h"
#include "passes/scene/scene.h"
#include "tests/fuzz/image_blob_input.h"

namespace nc = nightcap;
namespace fs = std::filesystem;

namespace {
namespace NIGHTCAP_FILE_ID {

const fs::path kCorpus = fs::path(NIGHTCAP_SOURCE) / "tests/fuzz/corpus";

std::vector<uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

template <class Error, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// OpenEXR reads a channel list to its end whatever size the header states; the header walk that
// bounded attribute sizes skipped by the stated size, so it and OpenEXR parted ways and OpenEXR
// went on to allocate a 2 GiB string.
TEST(FuzzRegressions, ExrChannelListPastItsStatedSize) {
  const std::vector<uint8_t> input = read_bytes(kCorpus / "image_blob/channel_list_past_its_size.exr");
  const auto parsed = nc::fuzz::parse_image_blob_input(input);
  ASSERT_TRUE(parsed);
  const fs::path blob = fs::path(testing::TempDir()) / "channel_list_past_its_size.exr";
  std::ofstream(blob, std::ios::binary)
      .write(reinterpret_cast<const char*>(parsed->blob.data()), std::streamsize(parsed->blob.size()));
  const std::string error =
      error_of<nc::CaptureError>([&] { nc::read_image_blob(blob, parsed->format, parsed->extent); });
  EXPECT_NE(error.find(blob.string() + ": has a channel list that does not end at its stated size"), std::string::npos)
      << error;
}

// tinygltf 2.7 hands an image's buffer view to the image callback without checking it lies in
// its buffer: the decoder read past the buffer (freed memory, under the fuzzer).
TEST(FuzzRegressions, GltfImageBufferViewOutsideItsBuffer) {
  const fs::path file = kCorpus / "gltf/image_view_outside_buffer.glb";
  const std::string error = error_of<nc::SceneError>([&] { nc::load_gltf(file.string()); });
  EXPECT_NE(error.find(file.string()), std::string::npos) << error;
  EXPECT_NE(error.find("its buffer view lies outside its buffer"), std::string::npos) << error;
}

// A frame that lists a pass twice (manifest_fuzz copied part of the pass list) made a diff of the
// capture with itself pair different versions and read blobs: the tools align by name, so a
// repeated frame index, pass name, or resource among a pass's inputs or outputs is refused.
TEST(FuzzRegressions, ManifestNamesThatRepeat) {
  const fs::path capture = fs::path(testing::TempDir()) / "pass_named_twice";
  fs::create_directories(capture);
  fs::copy_file(kCorpus / "manifest/pass_named_twice.json", capture / "manifest.json",
                fs::copy_options::overwrite_existing);
  std::string error = error_of<nc::CaptureError>([&] { nc::Capture::open(capture); });
  EXPECT_NE(error.find("pass 'exposure' appears twice in the frame"), std::string::npos) << error;

  const nlohmann::json valid = nlohmann::json::parse(read_bytes(kCorpus / "manifest/city_16x9_1frame.json"));
  const auto refused = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json manifest = valid;
    edit(manifest);
    return error_of<nc::CaptureError>([&] { nc::manifest_from_json(manifest, "edited.json"); });
  };
  error = refused([](nlohmann::json& m) { m["frames"].push_back(m["frames"][0]); });
  EXPECT_NE(error.find("frames[1]: frame 0 appears twice"), std::string::npos) << error;
  error = refused([](nlohmann::json& m) {
    for (nlohmann::json& pass : m["frames"][0]["passes"])
      if (!pass["outputs"].empty()) {
        pass["outputs"].push_back(pass["outputs"][0]);
        return;
      }
  });
  EXPECT_NE(error.find("appears twice among the outputs"), std::string::npos) << error;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
