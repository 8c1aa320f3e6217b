// `render --supersample N`: the reference TAA is measured against, as a capture: taa.supersampled
// in taa's place writes the mean of lighting.lit over N² renders offset across the pixel, replay
// says why it does not re-run it, and `report REF TAA` puts TAA's frame beside it with FLIP.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "captures/capture.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kStill = "--city-block --size 160x90 --motion static --freeze";

TEST(Supersample, TheReferenceCaptureHoldsTheMeanOfTheOffsetRendersInPlaceOfTaa) {
  const fs::path dir = scratch("supersample");
  const fs::path ref = dir / "ref", samples = dir / "samples", taa = dir / "taa";
  // The reference of frame 3, and the 16 renders it averages recorded one by one: frame k offset
  // to sample k of frame.constants.supersample's 4×4 pattern, TAA off.
  CliResult r = run_cli("render " + kStill + " --frames 4 --record-frames 3..3 --supersample 4 -o " + quote(ref));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("render " + kStill + " --frames 16 --set taa.enabled=0 --set frame.constants.supersample=4 -o " +
              quote(samples));
  ASSERT_EQ(r.code, 0) << r.err;

  const Capture reference = Capture::open(ref), renders = Capture::open(samples);
  const FrameRecord& frame = reference.frame(3);
  EXPECT_THROW(pass_named(frame, "taa"), std::runtime_error);
  const PassRecord& supersampled = pass_named(frame, "taa.supersampled");
  EXPECT_EQ(supersampled.stage, "taa");
  EXPECT_EQ(supersampled.params.at("samples"), 16.0);
  const std::vector<float> resolved = decoded_output(reference, frame, "taa.supersampled", "taa.resolved");
  ASSERT_EQ(resolved.size(), size_t(160) * 90 * 4);
  std::vector<double> mean(resolved.size(), 0.0);
  for (uint32_t k = 0; k < 16; ++k) {
    const std::vector<float> lit = decoded_output(renders, renders.frame(k), "lighting.composite", "lighting.lit");
    ASSERT_EQ(lit.size(), mean.size()) << "frame " << k;
    for (size_t i = 0; i < lit.size(); ++i) mean[i] += lit[i] / 16.0;
  }
  size_t beyond = 0;
  for (size_t i = 0; i < resolved.size(); ++i) {
    // Rounded to a half once: within half a unit in the last place (2^-11 relative) and the
    // smallest subnormal step.
    const double expected = i % 4 == 3 ? 1.0 : mean[i];
    beyond += std::abs(resolved[i] - expected) > std::abs(expected) * 0x1p-11 + 0x1p-24;
  }
  EXPECT_EQ(beyond, 0u);

  // Replay has no inputs to run it on, and says so; the other passes replay clean.
  r = run_cli("replay --verify --frame 3 --json " + quote(ref));
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  bool said = false;
  const json replay = json::parse(r.out);
  for (const json& pass : replay["passes"])
    if (pass["name"] == "taa.supersampled")
      said = pass["replayed"] == false && pass["reason"].get<std::string>().find("supersample") != std::string::npos;
  EXPECT_TRUE(said) << r.out;

  // TAA's frame 3 of the same still frame, against the reference: the frames agree up to taa,
  // and the displayed colour differs with a FLIP map in the report.
  r = run_cli("render " + kStill + " --frames 4 --record-frames 3..3 -o " + quote(taa));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cli("diff --json " + quote(ref) + " " + quote(taa));
  const json diff = json::parse(r.out);
  std::set<std::string> differing;
  double flip = -1;
  for (const json& pass : diff["frames"][0]["passes"]) {
    if (pass["status"] != "identical") differing.insert(pass["name"]);
    for (const json& o : pass.value("outputs", json::array()))
      if (o["resource"] == "final.ldr" && o.contains("flip")) flip = o["flip"]["mean"];
  }
  for (const char* pass : {"frame.constants", "lighting.composite", "gbuffer.opaque"})
    EXPECT_EQ(differing.count(pass), 0u) << pass << " differs: " << r.out;
  EXPECT_TRUE(differing.count("taa") && differing.count("taa.supersampled") && differing.count("tonemap")) << r.out;
  EXPECT_GT(flip, 0.0) << r.out;
  EXPECT_LT(flip, 0.2) << r.out;
  const fs::path out = dir / "report";
  r = run_cli("report " + quote(ref) + " " + quote(taa) + " -o " + quote(out));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(out / "index.html");
  const size_t card = html.find("data-output-name=\"tonemap/final.ldr\"");
  ASSERT_NE(card, std::string::npos);
  EXPECT_NE(html.find("data-view=\"flip\"", card), std::string::npos);
}

TEST(Supersample, NeedsAStillCameraAndAFrozenScene) {
  const fs::path out = scratch("supersample-refused") / "ref";
  for (const char* flags : {"--city-block --motion static", "--city-block --freeze",
                            "--city-block --motion static --freeze --frames 3 --cut-at 1"}) {
    const CliResult r = run_cli(std::string("render ") + flags + " --supersample 2 -o " + quote(out));
    EXPECT_EQ(r.code, 2) << flags;
    EXPECT_NE(r.err.find("--supersample 2 averages renders of one still frame"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << flags;
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
