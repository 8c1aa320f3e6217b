// Opening a capture reads its manifest and no blob: with every blob replaced by one that still
// decodes (same format, size and extent) but no longer matches its hash, `passes`, `graph` and a
// diff against the intact capture print what they printed before. Replaying a pass reads its
// blobs, and the first one it reads is refused by name for its hash.
#include <gtest/gtest.h>

#include "captures/capture.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/damaged_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

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

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
