// Stress cases of the sky through the command line, on the 1 km map at 161×91, two frames: the
// light on the horizon (`--hour 18`: the sun setting and the moon rising, both level), the sun 5°
// below it (`--hour 18.42`: the frame is lit by the moon 5° up, and the sky's LUTs see the light
// that low), the camera 8 km up, and the camera 8 km east and 8 km north of the origin (beyond
// the map's corner, the city in the distance through the air). The render exits 0, `inspect nan`
// finds no NaN or Inf in either frame, and `replay --verify` reproduces every pass that ran (the
// sky's and the composite among them) from its recorded inputs. The light below the horizon
// itself (-3°, -5°) is the LUTs' unit tests' (tests/unit/sky_test.cpp, sky_ibl_test.cpp).
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

class SkyStress : public ::testing::TestWithParam<Case> {};

TEST_P(SkyStress, FiniteEverywhereAndReplaysBitIdentically) {
  const fs::path capture = scratch(std::string("sky-") + GetParam().name) / "capture";
  const CliResult render =
      run_cli(std::string("render --map-size 1 --frames 2 --size 161x91 ") + GetParam().args + " -o " + quote(capture));
  ASSERT_EQ(render.code, 0) << render.err;
  for (const char* pass : {"sky.view", "sky.aerial_perspective", "sky.specular"}) {
    const Inspected info = inspect(capture, std::string("goto ") + pass + " --json; info --json");
    ASSERT_EQ(info.result.code, 0) << info.result.err;
    EXPECT_EQ(info.objects.at(1).at("status"), "ran") << pass << " in frame 0: " << info.objects.at(1).dump();
  }
  expect_no_nan_or_inf(capture);
  expect_replays_verify(capture);
}

INSTANTIATE_TEST_SUITE_P(Cases, SkyStress,
                         ::testing::Values(Case{"light_on_horizon", "--hour 18"},
                                           Case{"sun_5_degrees_below", "--hour 18.42"},
                                           Case{"camera_8km_up", "--hour 17 --orbit 20,30,9238"},
                                           Case{"camera_8km_out", "--hour 17 --orbit 45,85,60 --target 8000,2,-8000"}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
