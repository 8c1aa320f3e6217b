// Time of day through the command line: `bake-tod` writes a table, `render --hour --tod` reads it
// and `replay --verify` reproduces every pass bit for bit from the capture alone; a table for
// another map, a corrupt or truncated one, and flags that cannot go together exit 2 naming the
// problem.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

TEST(TodCli, BakeRenderReplay) {
  const fs::path dir = scratch("tod-cli");
  const fs::path table = dir / "map.tod";
  const CliResult bake = run_cli("bake-tod --scene-seed 2 --map-size 0.5 -o " + quote(table));
  ASSERT_EQ(bake.code, 0) << bake.err;
  EXPECT_NE(bake.out.find("12:00"), std::string::npos) << bake.out;
  EXPECT_TRUE(fs::exists(table));

  for (const char* hour : {"9", "20"}) {  // the sun, then the moon
    const fs::path capture = dir / (std::string("capture-") + hour);
    const CliResult render = run_cli("render --scene-seed 2 --map-size 0.5 --shot rooftop --size 160x90 --hour " +
                                     std::string(hour) + " --tod " + quote(table) + " -o " + quote(capture));
    ASSERT_EQ(render.code, 0) << render.err;
    const nlohmann::json manifest = read_json(capture / "manifest.json");
    EXPECT_EQ(manifest.at("settings").at("tod"), table.string());
    const CliResult replay = run_cli("replay --verify " + quote(capture));
    EXPECT_EQ(replay.code, 0) << replay.out << replay.err;
  }

  auto refused = [&](const std::string& args, const std::string& expected) {
    const CliResult r = run_cli(args + " --size 16x16 -o " + quote(dir / "refused"));
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << ": " << r.err;
  };
  refused("render --scene-seed 3 --map-size 0.5 --hour 9 --tod " + quote(table), "seed 2");
  refused("render --scene-seed 2 --map-size 1 --hour 9 --tod " + quote(table), "0.5 km");
  refused("render --scene-seed 2 --map-size 0.5 --tod " + quote(table), "--hour");
  refused("render --city-block --hour 9 --tod " + quote(table), "built-in map");
  refused("render --scene-seed 2 --map-size 0.5 --hour 24", "--hour");
  std::string bytes = slurp(table);
  const fs::path truncated = dir / "truncated.tod", corrupt = dir / "corrupt.tod";
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() - 5);
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(corrupt, std::ios::binary) << bytes;
  refused("render --scene-seed 2 --map-size 0.5 --hour 9 --tod " + quote(truncated),
          truncated.string() + ": truncated");
  refused("render --scene-seed 2 --map-size 0.5 --hour 9 --tod " + quote(corrupt), corrupt.string() + ": corrupt");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
