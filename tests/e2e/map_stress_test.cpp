// Stress cases of the built-in map through the command line: a 1×1 output, an odd one
// (161×91), each shot, two frames with traffic moving: the render exits 0, no pass writes a NaN
// or an Inf anywhere in either frame (`inspect nan` searches every recorded frame's float
// images, float depth and schema'd buffer fields), and `replay --verify` reproduces every pass that ran bit
// for bit from its recorded inputs.
#include <gtest/gtest.h>

#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

struct Case {
  const char* name;
  const char* args;
};

class MapStress : public ::testing::TestWithParam<Case> {};

TEST_P(MapStress, FiniteEverywhereAndReplaysBitIdentically) {
  const fs::path capture = scratch(std::string("map-") + GetParam().name) / "capture";
  const CliResult render =
      run_cli(std::string("render --map-size 1 --frames 2 ") + GetParam().args + " -o " + quote(capture));
  ASSERT_EQ(render.code, 0) << render.err;
  expect_no_nan_or_inf(capture);
  expect_replays_verify(capture);
}

INSTANTIATE_TEST_SUITE_P(Shots, MapStress,
                         ::testing::Values(Case{"street_1x1", "--shot street --size 1x1"},
                                           Case{"street_odd", "--shot street --size 161x91"},
                                           Case{"rooftop_odd", "--shot rooftop --size 161x91"},
                                           Case{"aerial_odd", "--shot aerial --size 161x91 --motion drive"}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
