// An empty scene renders instead of being refused, and every pass whose inputs are all cleared is
// skipped with that reason; lighting.composite, whose inputs are uniform (the sky), is folded.
// taa runs (its history makes its result unknown before the frame), and the passes after it with
// it. The capture records the skipped and folded passes' inputs, so `replay --verify`
// runs each of them, and every pass that ran, on the general path, and checks that the outputs
// are bit for bit what the frame recorded. No NaN or Inf appears in either of the two frames
// (`inspect nan` searches every recorded frame).
#include <gtest/gtest.h>

#include <fstream>

#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

struct Case {
  const char* name;
  const char* gltf;
  std::vector<std::string> skipped_for_cleared_inputs;
};

const std::set<std::string> kFolded = {"lighting.composite"};

class EmptyScene : public ::testing::TestWithParam<Case> {};

TEST_P(EmptyScene, RendersSkipsOrFoldsWhatItsKnownInputsDecideAndReplaysEveryPass) {
  const fs::path dir = scratch(std::string("empty-") + GetParam().name);
  const fs::path scene = dir / "scene.gltf", capture = dir / "capture";
  std::ofstream(scene) << GetParam().gltf;
  const CliResult render = run_cli("render " + quote(scene) + " --frames 2 --size 161x91 -o " + quote(capture));
  ASSERT_EQ(render.code, 0) << render.err;

  const CliResult passes = run_cli("passes --json " + quote(capture));
  ASSERT_EQ(passes.code, 0) << passes.err;
  const nlohmann::json listed = nlohmann::json::parse(passes.out);
  expect_no_nan_or_inf(capture);
  for (int frame : {0, 1}) {
    std::set<std::string> skipped_for_cleared_inputs, folded, ran;
    for (const auto& pass : listed["frames"][frame]["passes"]) {
      const std::string name = pass["name"], reason = pass.value("reason", "");
      if (pass["status"] == "ran") ran.insert(name);
      if (pass["status"] != "skipped") continue;
      if (reason.rfind("inputs all cleared (", 0) == 0) skipped_for_cleared_inputs.insert(name);
      if (reason.rfind("inputs uniform (", 0) == 0 && reason.ends_with("): folded")) folded.insert(name);
    }
    EXPECT_EQ(folded, kFolded) << "frame " << frame;
    EXPECT_TRUE(ran.count("exposure") && ran.count("tonemap")) << "frame " << frame;
    // Frame 1: the camera walks, so motion.stencil's own condition (nothing moves) no longer skips it.
    if (frame == 1) {
      EXPECT_EQ(skipped_for_cleared_inputs, std::set<std::string>(GetParam().skipped_for_cleared_inputs.begin(),
                                                                  GetParam().skipped_for_cleared_inputs.end()));
    }
    const CliResult replay = run_cli("replay --verify --json --frame " + std::to_string(frame) + " " + quote(capture));
    ASSERT_EQ(replay.code, 0) << "frame " << frame << ": " << replay.out << replay.err;
    std::set<std::string> replayed;
    const nlohmann::json report = nlohmann::json::parse(replay.out);
    for (const auto& pass : report["passes"])
      if (pass["replayed"].get<bool>()) replayed.insert(pass["name"].get<std::string>());
    for (const auto& passes : {skipped_for_cleared_inputs, folded, ran})
      for (const std::string& pass : passes)
        EXPECT_TRUE(replayed.count(pass)) << pass << " was not replayed in frame " << frame;
  }
}

const char* kEmpty = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}], "nodes": []})";
// A point light and nothing for it to light.
const char* kLightOnly = R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10, "range": 5}]}},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}]})";

INSTANTIATE_TEST_SUITE_P(Scenes, EmptyScene,
                         ::testing::Values(Case{"nothing",
                                                kEmpty,
                                                {"depth.convert", "motion.stencil", "normals.pack", "normals.half",
                                                 "depth.pyramid", "ao.gtao", "ao.filter", "ao.temporal"}},
                                           Case{"light_only",
                                                kLightOnly,
                                                {"depth.convert", "motion.stencil", "normals.pack", "normals.half",
                                                 "depth.pyramid", "ao.gtao", "ao.filter", "ao.temporal",
                                                 "lighting.tiled"}}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
