// The sun's shadows across frames end to end: 4-frame captures of the 2 km map's street shot
// with a still camera (vehicles moving) and a driving one. Frame 3 replays bit-identically from
// its own record, the previous frames' static cascade depth being a declared history input; the
// recorded shadow.cull_stats say frame 0 reset the cascades' static layers, a still camera kept
// them whole from frame 1 on (nothing redrawn) and a driving one moved them and redrew what they
// uncovered within the budget, none pending; the recorded distant plans redraw every level at frame 0 (the
// history reset), stay within the budget after, and draw nothing for a still camera. The
// built-in city's spot light maps likewise: frame 3 replays from its own record (the plan's
// previous record and the static slots' previous depth being history inputs), frame 0 refreshes
// every map and frames 1-3 reuse them.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "captures/capture.h"
#include "passes/shadow/local_layout.h"
#include "passes/shadow/shadow_layout.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

const ResourceRecord* find_resource(const FrameRecord& frame, const std::string& pass, const std::string& resource,
                                    bool output) {
  for (const PassRecord& p : frame.passes)
    if (p.name == pass)
      for (const ResourceRecord& r : output ? p.outputs : p.inputs)
        if (r.resource == resource) return &r;
  return nullptr;
}

template <typename Record>
Record load_record(const Capture& capture, const ResourceRecord& resource) {
  const std::vector<uint8_t> bytes = capture.load(resource);
  Record r{};
  EXPECT_EQ(bytes.size(), sizeof r) << resource.resource;
  if (bytes.size() == sizeof r) std::memcpy(&r, bytes.data(), sizeof r);
  return r;
}

TEST(ShadowCache, FrameThreeReplaysAndTheRecordsSayWhatWasKept) {
  for (const bool still : {true, false}) {
    SCOPED_TRACE(still ? "still camera" : "driving");
    const std::filesystem::path path = shared_capture(
        still ? "shadow-cache-still" : "shadow-cache-drive",
        std::string("--map-size 2 --shot street --size 160x90 --frames 4 --motion ") + (still ? "static" : "drive"));
    const CliResult r = run_cli("replay --verify --json --frame 3 " + quote(path));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    EXPECT_FALSE(report.at("different").get<bool>());
    bool statics_replayed = false;
    for (const auto& p : report.at("passes")) {
      statics_replayed |= p.at("name") == "shadow.cascades_static" && p.at("replayed").get<bool>();
      for (const auto& o : p.value("outputs", nlohmann::json::array()))
        EXPECT_EQ(o.at("verdict"), "identical") << p.at("name") << " " << o.at("resource");
    }
    EXPECT_TRUE(statics_replayed);

    const Capture capture = Capture::open(path);
    ASSERT_EQ(capture.manifest().frames.size(), 4u);
    for (uint32_t k = 0; k < 4; ++k) {
      const FrameRecord& frame = capture.frame(k);
      const ResourceRecord* stats_record = find_resource(frame, "shadow.cull", "shadow.cull_stats", true);
      const ResourceRecord* plan_record = find_resource(frame, "shadow.distant_plan", "shadow.distant_plan", true);
      ASSERT_TRUE(stats_record && plan_record) << "frame " << k;
      const auto stats = load_record<ShadowCullStats>(capture, *stats_record);
      const auto plan = load_record<DistantPlan>(capture, *plan_record);
      EXPECT_EQ(stats.reset, uint32_t(k == 0 ? CascadeReset::no_history : CascadeReset::none)) << "frame " << k;
      uint64_t refreshed = stats.strips, moved = 0;
      for (uint32_t c = 0; c < kShadowCascades; ++c) {
        refreshed |= ShadowCullStats::mask(stats.refreshed, c);
        moved |= uint64_t(stats.shift[2 * c] != 0 || stats.shift[2 * c + 1] != 0);
      }
      if (k > 0) {
        EXPECT_EQ(stats.pending, 0u) << "frame " << k;
        EXPECT_TRUE(stats.static_triangles <= stats.budget_triangles || stats.over_budget) << "frame " << k;
        EXPECT_EQ(refreshed != 0, !still) << "frame " << k << ": only a moving camera redraws static texels";
        EXPECT_EQ(moved != 0, !still) << "frame " << k;
      }
      EXPECT_EQ(plan.reset, k == 0 ? 1u : 0u) << "frame " << k;
      if (k == 0) {
        for (uint32_t level = 0; level < kDistantLevels; ++level)
          EXPECT_EQ(plan.refreshed[level], (1u << (plan.tiles_per_side * plan.tiles_per_side)) - 1u) << level;
      } else {
        EXPECT_TRUE(plan.triangles <= plan.budget_triangles || plan.over_budget) << "frame " << k;
        if (still) {
          EXPECT_EQ(plan.draws, 0u) << "frame " << k << ": a still camera's levels are complete";
        }
      }
      if (still && k > 0) {
        const ResourceRecord* history =
            find_resource(frame, "shadow.cascades_static", "shadow.cascades_static@previous", false);
        const ResourceRecord* before =
            find_resource(capture.frame(k - 1), "shadow.cascades_static", "shadow.cascades_static", true);
        ASSERT_TRUE(history && before) << "frame " << k;
        EXPECT_EQ(history->hash, before->hash)
            << "frame " << k << " read something else than frame " << k - 1 << " wrote";
      }
    }
  }
}

TEST(ShadowCache, SpotLightMapsAreKeptAndFrameThreeReplays) {
  const std::filesystem::path path =
      shared_capture("local-cache-still", "--city-block --size 160x90 --frames 4 --motion static");
  const CliResult r = run_cli("replay --verify --json --frame 3 " + quote(path));
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_FALSE(report.at("different").get<bool>());
  std::set<std::string> replayed;
  for (const auto& p : report.at("passes")) {
    if (p.at("replayed").get<bool>()) replayed.insert(p.at("name").get<std::string>());
    for (const auto& o : p.value("outputs", nlohmann::json::array()))
      EXPECT_EQ(o.at("verdict"), "identical") << p.at("name") << " " << o.at("resource");
  }
  for (const char* pass : {"shadow.local_plan", "shadow.local_static", "shadow.local", "shadow.local_moments"})
    EXPECT_TRUE(replayed.count(pass)) << pass;

  const Capture capture = Capture::open(path);
  ASSERT_EQ(capture.manifest().frames.size(), 4u);
  for (uint32_t k = 0; k < 4; ++k) {
    const FrameRecord& frame = capture.frame(k);
    const ResourceRecord* record = find_resource(frame, "shadow.local_plan", "shadow.local_plan", true);
    ASSERT_TRUE(record) << "frame " << k;
    const auto plan = load_record<LocalShadowPlan>(capture, *record);
    EXPECT_GT(plan.maps, 0u) << "frame " << k;
    EXPECT_EQ(plan.reset, k == 0 ? 1u : 0u) << "frame " << k;
    EXPECT_EQ(plan.reused, k == 0 ? 0u : plan.maps) << "frame " << k;
    for (uint32_t m = 0; m < plan.maps; ++m)
      EXPECT_EQ(plan.slot_state[plan.slice_slot[m]],
                uint32_t(k == 0 ? LocalSlotState::refreshed_reset : LocalSlotState::reused))
          << "frame " << k << ", map " << m;
    if (k > 0) {
      const ResourceRecord* history =
          find_resource(frame, "shadow.local_static", "shadow.local_static@previous", false);
      const ResourceRecord* before =
          find_resource(capture.frame(k - 1), "shadow.local_static", "shadow.local_static", true);
      ASSERT_TRUE(history && before) << "frame " << k;
      EXPECT_EQ(history->hash, before->hash)
          << "frame " << k << " read something else than frame " << k - 1 << " wrote";
    }
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
