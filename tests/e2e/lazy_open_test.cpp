// Opening a capture reads its manifest and no blob: with every blob replaced by one that still
// decodes (same format, size and extent) but no longer matches its hash, `passes`, `graph` and a
// diff against the intact capture print what they printed before. Replaying a pass reads its
// blobs, and the first one it reads is refused by name for its hash.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "captures/capture.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace fs = std::filesystem;

void overwrite_with(const fs::path& file, char fill) {
  const auto size = fs::file_size(file);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << std::string(size, fill);
}

// Resources get blobs that decode to other bytes of the same size, so only the hash can tell;
// shader blobs keep their size (SPIR-V: a whole number of words) and lose their content.
void damage_every_blob(const fs::path& folder) {
  const Capture capture = Capture::open(folder);
  std::set<std::string> done;
  for (const FrameRecord& frame : capture.manifest().frames)
    for (const PassRecord& pass : frame.passes) {
      for (const auto* side : {&pass.inputs, &pass.outputs})
        for (const ResourceRecord& r : *side) {
          if (!done.insert(r.blob).second) continue;
          std::vector<uint8_t> raw(r.raw_bytes(), 0);
          if (!raw.empty()) raw[0] = 1;  // a low bit of the first texel's first channel: valid in any format
          if (r.is_buffer)
            write_buffer_blob(folder / r.blob, raw, 3);
          else
            write_image_blob(folder / r.blob, *format_info(r.format), r.extent, raw, {ExrCompression::zip});
        }
      for (const ShaderRecord& s : pass.shaders)
        for (const std::string& blob : {s.blob, s.source_blob})
          if (done.insert(blob).second) overwrite_with(folder / blob, 'x');
    }
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder / "blobs")) ++files;
  ASSERT_EQ(files, done.size()) << "a blob the manifest does not name";
}

TEST(LazyOpen, PassesGraphAndDiffReadNoBlob) {
  const fs::path intact = shared_capture("city-small", "--city-block --size 64x36");
  const fs::path capture = scratch("damaged") / "capture";
  fs::copy(intact, capture, fs::copy_options::recursive);
  const std::vector<std::string> commands = {"passes " + quote(capture), "passes --json " + quote(capture),
                                             "graph --dot " + quote(capture),
                                             "diff " + quote(intact) + " " + quote(capture)};
  std::vector<std::string> before;
  for (const std::string& command : commands) {
    const CliResult r = run_cli(command);
    ASSERT_EQ(r.code, 0) << command << ": " << r.err;
    before.push_back(r.out);
  }
  damage_every_blob(capture);
  for (size_t i = 0; i < commands.size(); ++i) {
    const CliResult r = run_cli(commands[i]);
    EXPECT_EQ(r.code, 0) << commands[i] << ": " << r.err;
    EXPECT_EQ(r.out, before[i]) << commands[i];
  }

  const CliResult replay = run_cli("replay --verify --pass tonemap " + quote(capture));
  EXPECT_EQ(replay.code, 2) << replay.out << replay.err;
  const PassRecord* tonemap = nullptr;
  const Capture opened = Capture::open(capture);
  for (const PassRecord& p : opened.frame(0).passes)
    if (p.name == "tonemap") tonemap = &p;
  ASSERT_NE(tonemap, nullptr);
  std::vector<std::pair<std::string, std::string>> blobs;  // blob, hash
  for (const ResourceRecord& r : tonemap->inputs) blobs.emplace_back(r.blob, r.hash);
  for (const ShaderRecord& s : tonemap->shaders) blobs.emplace_back(s.blob, s.hash);
  bool named = false;
  for (const auto& [blob, hash] : blobs)
    named |= replay.err.find(blob + ": content does not match its hash " + hash) != std::string::npos;
  EXPECT_TRUE(named) << "no blob of tonemap named with its hash: " << replay.err;
}

}  // namespace
}  // namespace nightcap::test
