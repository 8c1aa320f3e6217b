// Goldens through the CLI: `golden update` into a store, `golden list`, and `diff --golden`
// with the flags of a two-capture diff, what one side lacks named for the side, a missing golden,
// and names and argument mixtures that are refused.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kSmall = "--city-block --size 64x36 --frames 1";
const std::string kSmallLight = kSmall + " --set lighting.tiled.intensity_scale=1.5";

std::string last_line(const std::string& text) {
  std::string trimmed = text;
  while (!trimmed.empty() && trimmed.back() == '\n') trimmed.pop_back();
  return trimmed.substr(trimmed.rfind('\n') == std::string::npos ? 0 : trimmed.rfind('\n') + 1);
}

std::set<std::string> names_in(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

CliResult update(const fs::path& capture, const fs::path& store, const std::string& name) {
  return run_cli("golden update " + quote(capture) + " --store " + quote(store) + " --name " + quote(name));
}

TEST(GoldenDiff, TheSameCaptureAgainstItsGoldenPasses) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path store = scratch("store") / "goldens-store";
  const CliResult recorded = update(capture, store, "city");
  ASSERT_EQ(recorded.code, 0) << recorded.err;

  // One copy of each blob, in the store: the golden's folder holds its manifest and picture.
  EXPECT_TRUE(fs::is_regular_file(store / "nightcap-store.json"));
  EXPECT_EQ(names_in(store / "blobs"), names_in(capture / "blobs"));
  EXPECT_EQ(names_in(store / "goldens" / "city"), (std::set<std::string>{"manifest.json", "final.png"}));
  EXPECT_EQ(read_json(store / "goldens" / "city" / "manifest.json").at("blobs"), "store");

  const CliResult r = run_cli("diff --golden city --store " + quote(store) + " " + quote(capture));
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_TRUE(std::regex_match(last_line(r.out), std::regex("[1-9][0-9]* passed, 0 failed"))) << r.out;
  EXPECT_NE(r.out.find("no differences"), std::string::npos) << r.out;
}

TEST(GoldenDiff, AChangedCaptureFailsAndEveryFlagWorksAsForTwoCaptures) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path light = shared_capture("golden-small-light", kSmallLight);
  const fs::path dir = scratch("flags"), store = dir / "store";
  ASSERT_EQ(update(capture, store, "city").code, 0);
  std::ofstream(dir / "t.json") << R"({"thresholds": [{"match": "lighting.*/*", "metric": "rel", "limit": 1e9}]})";

  const CliResult r = run_cli("diff --json --golden city --store " + quote(store) + " " + quote(light));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(json::parse(r.out).at("first_divergence"), (json{{"frame", 0}, {"pass", "lighting.tiled"}}));

  // The golden is capture A: the same flags give what the two captures give, JUnit (but for
  // its timings) included.
  for (const std::string& flags : std::vector<std::string>{"--json", "--json --frame 0 --tolerance 0.5",
                                                           "--json --thresholds " + quote(dir / "t.json"), ""}) {
    const CliResult golden = run_cli("diff " + flags + " --junit " + quote(dir / "golden.xml") + " --golden city " +
                                     "--store " + quote(store) + " " + quote(light));
    const CliResult plain =
        run_cli("diff " + flags + " --junit " + quote(dir / "plain.xml") + " " + quote(capture) + " " + quote(light));
    EXPECT_EQ(golden.code, plain.code) << flags;
    EXPECT_EQ(golden.out, plain.out) << flags;
    EXPECT_EQ(golden.err, plain.err) << flags;
    const std::regex time(" time=\"[^\"]*\"");
    EXPECT_EQ(std::regex_replace(slurp(dir / "golden.xml"), time, ""),
              std::regex_replace(slurp(dir / "plain.xml"), time, ""))
        << flags;
  }
  const CliResult frame = run_cli("diff --frame 3 --golden city --store " + quote(store) + " " + quote(light));
  EXPECT_EQ(frame.code, 2);
  EXPECT_NE(frame.err.find("no frame 3"), std::string::npos) << frame.err;
}

TEST(GoldenDiff, AMissingGoldenIsItsOwnResult) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path store = scratch("missing") / "store";
  for (const bool recorded : {false, true}) {
    if (recorded) {
      ASSERT_EQ(update(capture, store, "other").code, 0);
    }
    const CliResult r = run_cli("diff --golden city --store " + quote(store) + " " + quote(capture));
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "nightcap: golden 'city' missing from store " + store.string() +
                         " (record it with: nightcap golden update " + capture.string() + " --store " + store.string() +
                         " --name city)\n");
    EXPECT_EQ(r.out, "");
  }
}

TEST(GoldenDiff, HostileNamesAreRefusedAndWriteNothing) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path dir = scratch("hostile"), store = dir / "store";
  ASSERT_EQ(update(capture, store, "city").code, 0);
  const std::set<std::string> beside = names_in(dir), blobs = names_in(store / "blobs"),
                              goldens = names_in(store / "goldens");
  for (const std::string name : {"../x", "a/b", "", "..", "../../escaped"}) {
    const CliResult r = update(capture, store, name);
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_NE(r.err.find("--name '" + name + "': not a golden name"), std::string::npos) << r.err;
    const CliResult d = run_cli("diff --golden " + quote(name) + " --store " + quote(store) + " " + quote(capture));
    EXPECT_EQ(d.code, 2) << name;
    EXPECT_NE(d.err.find("--golden '" + name + "': not a golden name"), std::string::npos) << d.err;
  }
  EXPECT_EQ(names_in(dir), beside);
  EXPECT_EQ(names_in(store / "blobs"), blobs);
  EXPECT_EQ(names_in(store / "goldens"), goldens);
  EXPECT_TRUE(fs::is_empty(store / "tmp"));
  EXPECT_FALSE(fs::exists(dir.parent_path() / "escaped"));
}

TEST(GoldenDiff, ADamagedCaptureLeavesTheStoreAsItWas) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path light = shared_capture("golden-small-light", kSmallLight);
  const fs::path dir = scratch("damaged"), store = dir / "store", damaged = dir / "damaged";
  ASSERT_EQ(update(capture, store, "city").code, 0);
  fs::copy(light, damaged, fs::copy_options::recursive);
  // A blob the store does not hold: brighter lights made a final.ldr of other bytes.
  const json manifest = read_json(damaged / "manifest.json");
  fs::path blob;
  for (const json& pass : manifest.at("frames")[0].at("passes"))
    for (const json& out : pass.at("outputs"))
      if (out.at("resource") == "final.ldr") blob = damaged / out.at("blob").get<std::string>();
  ASSERT_FALSE(blob.empty());
  ASSERT_FALSE(fs::exists(store / "blobs" / blob.filename()));
  const std::set<std::string> blobs = names_in(store / "blobs");
  const std::string golden = slurp(store / "goldens" / "city" / "manifest.json");
  std::ofstream(blob, std::ios::binary | std::ios::trunc) << std::string(64, 'x');

  for (const std::string name : {"city", "new"}) {
    const CliResult r = update(damaged, store, name);
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_NE(r.err.find(blob.string()), std::string::npos) << r.err;
    EXPECT_EQ(names_in(store / "blobs"), blobs);
    EXPECT_EQ(names_in(store / "goldens"), (std::set<std::string>{"city"}));
    EXPECT_EQ(slurp(store / "goldens" / "city" / "manifest.json"), golden);
    EXPECT_TRUE(fs::is_empty(store / "tmp"));
  }
}

TEST(GoldenDiff, TwoCapturesOrAGoldenAndOneNeverBoth) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path store = scratch("mixture") / "store";
  ASSERT_EQ(update(capture, store, "city").code, 0);
  const std::string golden = " --golden city --store " + quote(store);
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {golden + " " + quote(capture) + " " + quote(capture), "give one capture, not two"},
           {golden, "the capture to compare is missing"},
           {" --golden city " + quote(capture), "--golden requires --store"},
           {" --store " + quote(store) + " " + quote(capture) + " " + quote(capture), "--store requires --golden"},
           {" " + quote(capture), "diff needs two captures"}}) {
    const CliResult r = run_cli("diff" + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
  }
}

TEST(GoldenDiff, ListNamesTheGoldens) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path light = shared_capture("golden-small-light", kSmallLight);
  const fs::path store = scratch("list") / "store";
  ASSERT_EQ(update(capture, store, "city").code, 0);
  ASSERT_EQ(update(light, store, "bright").code, 0);
  // The two renders share every blob up to lighting.tiled: the store keeps one of each.
  std::set<std::string> both = names_in(capture / "blobs");
  for (const std::string& name : names_in(light / "blobs")) both.insert(name);
  EXPECT_EQ(names_in(store / "blobs"), both);
  EXPECT_LT(both.size(), names_in(capture / "blobs").size() + names_in(light / "blobs").size());

  const CliResult r = run_cli("golden list --json --store " + quote(store));
  ASSERT_EQ(r.code, 0) << r.err;
  const json list = json::parse(r.out);
  ASSERT_EQ(list.at("goldens").size(), 2u);
  const json& city = list.at("goldens")[1];
  EXPECT_EQ(list.at("goldens")[0].at("name"), "bright");
  EXPECT_EQ(city.at("name"), "city");
  EXPECT_EQ(city.at("frames"), 1);
  EXPECT_GT(city.at("passes").get<int>(), 10);
  EXPECT_EQ(city.at("source"), fs::absolute(capture).lexically_normal().string());
  EXPECT_TRUE(std::regex_match(city.at("updated").get<std::string>(),
                               std::regex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z")));
  const CliResult text = run_cli("golden list --store " + quote(store));
  EXPECT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("city"), std::string::npos) << text.out;

  const CliResult not_a_store = run_cli("golden list --store " + quote(capture));
  EXPECT_EQ(not_a_store.code, 2);
  EXPECT_NE(not_a_store.err.find("nightcap-store.json: missing (not a golden store)"), std::string::npos)
      << not_a_store.err;
}

// A copy of `capture` lacking the pass `tonemap` and the output gbuffer.normal of gbuffer.opaque,
// with a frame 1 that the capture lacks.
fs::path edited_copy(const fs::path& capture, const fs::path& copy) {
  fs::copy(capture, copy, fs::copy_options::recursive);
  json manifest = read_json(copy / "manifest.json");
  json& passes = manifest["frames"][0]["passes"];
  for (auto pass = passes.begin(); pass != passes.end(); ++pass)
    if (pass->at("name") == "tonemap") {
      passes.erase(pass);
      break;
    }
  for (json& pass : passes)
    if (pass.at("name") == "gbuffer.opaque") {
      json& outputs = pass["outputs"];
      for (auto out = outputs.begin(); out != outputs.end(); ++out)
        if (out->at("resource") == "gbuffer.normal") {
          outputs.erase(out);
          break;
        }
    }
  json extra = manifest["frames"][0];
  extra["index"] = 1;
  manifest["frames"].push_back(extra);
  write_json(copy / "manifest.json", manifest);
  return copy;
}

json output_named(const json& diff, const std::string& pass, const std::string& resource) {
  for (const json& p : diff.at("frames")[0].at("passes"))
    if (p.at("name") == pass)
      for (const json& o : p.at("outputs"))
        if (o.at("resource") == resource) return o;
  return nullptr;
}

json pass_named(const json& diff, const std::string& pass) {
  for (const json& p : diff.at("frames")[0].at("passes"))
    if (p.at("name") == pass) return p;
  return nullptr;
}

TEST(GoldenDiff, WhatOneSideLacksIsNamedForTheSide) {
  const fs::path capture = shared_capture("golden-small", kSmall);
  const fs::path dir = scratch("sides"), store = dir / "store";
  const fs::path edited = edited_copy(capture, dir / "edited");
  ASSERT_EQ(update(capture, store, "full").code, 0);
  ASSERT_EQ(update(edited, store, "partial").code, 0);

  struct Case {
    std::string golden;
    fs::path checked;
    std::string lacks_pass_and_output, lacks_frame;  // who lacks what
  };
  for (const Case& c : {Case{"full", edited, "output", "golden"}, Case{"partial", capture, "golden", "output"}}) {
    const std::string args = "--golden " + c.golden + " --store " + quote(store) + " " + quote(c.checked);
    const CliResult r = run_cli("diff --json --junit " + quote(dir / "diff.xml") + " " + args);
    EXPECT_EQ(r.code, 1) << r.err;
    const json diff = json::parse(r.out);
    const json normal = output_named(diff, "gbuffer.opaque", "gbuffer.normal");
    ASSERT_TRUE(normal.is_object()) << c.golden;
    EXPECT_EQ(normal.at("missing"), c.lacks_pass_and_output);
    EXPECT_EQ(normal.at("note"), c.lacks_pass_and_output + " missing");
    EXPECT_EQ(pass_named(diff, "tonemap").at("status"), c.lacks_pass_and_output + "_missing");
    EXPECT_EQ(diff.at("notes"), json::array({"frame 1: " + c.lacks_frame + " missing"}));
    const std::string xml = slurp(dir / "diff.xml");
    EXPECT_NE(xml.find("name=\"gbuffer.opaque/gbuffer.normal\">\n      <failure message=\"" + c.lacks_pass_and_output +
                       " missing\""),
              std::string::npos)
        << xml;
    EXPECT_NE(xml.find("name=\"tonemap\">\n      <failure message=\"" + c.lacks_pass_and_output + "_missing\""),
              std::string::npos)
        << xml;
    const CliResult table = run_cli("diff " + args);
    EXPECT_NE(table.out.find(c.lacks_pass_and_output + " missing"), std::string::npos) << table.out;
    EXPECT_NE(table.out.find(c.lacks_pass_and_output + "_missing"), std::string::npos) << table.out;
  }
  // Between two captures the wording stays A and B.
  const CliResult plain = run_cli("diff --json " + quote(capture) + " " + quote(edited));
  const json diff = json::parse(plain.out);
  EXPECT_EQ(output_named(diff, "gbuffer.opaque", "gbuffer.normal").at("note"), "only in A");
  EXPECT_FALSE(output_named(diff, "gbuffer.opaque", "gbuffer.normal").contains("missing"));
  EXPECT_EQ(pass_named(diff, "tonemap").at("status"), "only_in_a");
  EXPECT_EQ(diff.at("notes"), json::array({"frame 1 only in B"}));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
