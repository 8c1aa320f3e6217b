// ao.gtao in the frame (`--set ao.enabled=1`, off by default until its filter and temporal pass
// land): it runs, replays from its record bit for bit, `inspect pixel` decodes its visibility,
// cone and bent normal, and the composite, which reads ao.bent, darkens where it occludes;
// by default it is skipped as disabled and ao.bent reads unoccluded.
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

TEST(Ao, InTheCityFrameItRunsReplaysAndInspectDecodesIt) {
  const fs::path dir = scratch("ao");
  const fs::path on = dir / "on";
  CliResult r = run_cli("render --city-block --size 320x180 --set ao.enabled=1 -o " + quote(on));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("passes --json " + quote(on));
  ASSERT_EQ(r.code, 0) << r.err;
  const json listed = json::parse(r.out);
  const json* gtao = pass_in(listed["frames"][0], "ao.gtao");
  ASSERT_NE(gtao, nullptr);
  EXPECT_EQ((*gtao)["status"], "ran");

  r = run_cli("replay --verify --pass ao.gtao --pass lighting.composite " + quote(on));
  EXPECT_EQ(r.code, 0) << r.out << r.err;

  // A pixel of the street: its visibility, the cone that visibility gives and a unit bent normal.
  const Inspected run = inspect(on, "goto ao.gtao --json; pixel 300 160 ao.bent --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2u) << run.result.out;
  const json& values = run.objects[1]["decoded"];
  ASSERT_TRUE(values.contains("visibility")) << run.result.out;
  const double visibility = values["visibility"];
  EXPECT_GT(visibility, 0.0);
  EXPECT_LE(visibility, 1.0);
  EXPECT_NEAR(double(values["cone_half_angle_deg"]), std::asin(std::sqrt(visibility)) * 180 / M_PI, 1e-6);
  ASSERT_TRUE(values["bent_normal"].is_array()) << run.result.out;
  double length = 0;
  for (const json& c : values["bent_normal"]) length += double(c) * double(c);
  EXPECT_NEAR(length, 1.0, 1e-6);

  const fs::path off = dir / "off";
  r = run_cli("render --city-block --size 320x180 -o " + quote(off));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("passes --json " + quote(off));
  const json listed_off = json::parse(r.out);
  const json* skipped = pass_in(listed_off["frames"][0], "ao.gtao");
  ASSERT_NE(skipped, nullptr);
  EXPECT_EQ((*skipped)["status"], "skipped");
  // AO darkens the indirect light only where it occludes: the lit colour differs, the G-buffer
  // does not.
  r = run_cli("diff --json " + quote(off) + " " + quote(on));
  const json diff = json::parse(r.out);
  std::set<std::string> differing;
  for (const json& pass : diff["frames"][0]["passes"])
    if (pass["status"] != "identical") differing.insert(pass["name"]);
  EXPECT_TRUE(differing.count("lighting.composite")) << r.out;
  EXPECT_FALSE(differing.count("gbuffer.opaque")) << r.out;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
