// The AO chain in the city frame, on by default: ao.gtao → ao.filter → ao.temporal run; over
// still frames each replays from its record (ao.temporal with its history, ao.history and
// depth.half of the frame before) bit for bit, and ao.gtao with slabs (a positive thickness)
// too; `inspect pixel` decodes the visibility, cone and bent normal of ao.bent and the frames of
// ao.history; the composite, which reads ao.bent, differs from a frame with `--set
// ao.enabled=0`, where all three are skipped as disabled and the G-buffer is the same.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const json* pass_in(const json& frame, const std::string& name) {
  for (const json& pass : frame["passes"])
    if (pass["name"] == name) return &pass;
  return nullptr;
}

const std::vector<std::string> kChain = {"ao.gtao", "ao.filter", "ao.temporal"};

TEST(Ao, TheChainRunsReplaysWithItsHistoryAndInspectDecodesIt) {
  const fs::path dir = scratch("ao");
  const fs::path on = dir / "on";
  CliResult r = run_cli("render --city-block --size 320x180 --frames 3 --motion static --freeze -o " + quote(on));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("passes --json " + quote(on));
  ASSERT_EQ(r.code, 0) << r.err;
  const json listed = json::parse(r.out);
  for (const std::string& name : kChain) {
    const json* pass = pass_in(listed["frames"][2], name);
    ASSERT_NE(pass, nullptr) << name;
    EXPECT_EQ((*pass)["status"], "ran") << name;
  }

  r = run_cli("replay --verify --pass ao.gtao --pass ao.filter --pass ao.temporal --pass lighting.composite " +
              quote(on));
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  // ao.gtao's other pipeline, slabs of a positive thickness, replays bit for bit too.
  const fs::path slabs = dir / "slabs";
  r = run_cli("render --city-block --size 320x180 --frames 2 --motion static --freeze --set ao.gtao.thickness=0.5 -o " +
              quote(slabs));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("replay --verify --pass ao.gtao " + quote(slabs));
  EXPECT_EQ(r.code, 0) << r.out << r.err;

  // A pixel of the street in the third still frame: its visibility, the cone that visibility
  // gives, a unit bent normal; the history averages the three frames.
  const Inspected run = inspect(
      on, "frame 2 --json; goto ao.temporal --json; pixel 300 160 ao.bent --json; pixel 300 160 ao.history --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 4u) << run.result.out;
  const json& values = run.objects[2]["decoded"];
  ASSERT_TRUE(values.contains("visibility")) << run.result.out;
  const double visibility = values["visibility"];
  EXPECT_GT(visibility, 0.0);
  EXPECT_LE(visibility, 1.0);
  EXPECT_NEAR(double(values["cone_half_angle_deg"]), std::asin(std::sqrt(visibility)) * 180 / M_PI, 1e-6);
  ASSERT_TRUE(values["bent_normal"].is_array()) << run.result.out;
  double length = 0;
  for (const json& c : values["bent_normal"]) length += double(c) * double(c);
  EXPECT_NEAR(length, 1.0, 1e-6);
  EXPECT_NEAR(double(run.objects[3]["decoded"]["frames"]), 3.0, 0.01) << run.result.out;

  const fs::path off = dir / "off";
  r = run_cli("render --city-block --size 320x180 --frames 3 --motion static --freeze --set ao.enabled=0 -o " +
              quote(off));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("passes --json " + quote(off));
  const json listed_off = json::parse(r.out);
  for (const std::string& name : kChain) {
    const json* skipped = pass_in(listed_off["frames"][2], name);
    ASSERT_NE(skipped, nullptr) << name;
    EXPECT_EQ((*skipped)["status"], "skipped") << name;
  }
  // AO darkens the indirect light only where it occludes: the lit colour differs, the G-buffer
  // does not.
  r = run_cli("diff --json " + quote(off) + " " + quote(on));
  const json diff = json::parse(r.out);
  std::set<std::string> differing;
  for (const json& pass : diff["frames"][2]["passes"])
    if (pass["status"] != "identical") differing.insert(pass["name"]);
  EXPECT_TRUE(differing.count("lighting.composite")) << r.out;
  EXPECT_FALSE(differing.count("gbuffer.opaque")) << r.out;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
