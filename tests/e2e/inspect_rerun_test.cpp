// The inspect commands that look past one recorded value: `pick` (which draw covers a pixel),
// `history` (a pixel through the frame) and `replay` (the current pass again, with overrides).
// Each is checked against what is computed here from the capture's blobs: the draws rasterised on
// the CPU with the recorded camera (tests/reference/draw_raster_reference.h), stencil and depth
// planes read by their byte layout.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>
#include <optional>

#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "tests/e2e/inspect_script.h"
#include "tests/reference/draw_raster_reference.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

template <typename T>
T at(const std::vector<uint8_t>& raw, uint64_t offset) {
  T value;
  std::memcpy(&value, raw.data() + offset, sizeof(T));
  return value;
}

// D32_SFLOAT_S8_UINT in the raw layout: the depth plane (4 bytes a texel), then the stencil
// plane (1 byte a texel).
float depth_at(const std::vector<uint8_t>& raw, uint32_t width, uint32_t x, uint32_t y) {
  return at<float>(raw, 4 * (uint64_t(y) * width + x));
}
uint8_t stencil_at(const std::vector<uint8_t>& raw, uint32_t width, uint32_t height, uint32_t x, uint32_t y) {
  return raw[4 * uint64_t(width) * height + uint64_t(y) * width + x];
}

class InspectRerunTest : public CityCaptureTest {};

// How far the depth gbuffer.opaque wrote may be from the reference's at a pixel centre: 2^-18 of
// it, 32 float ulps. The GPU transforms the float vertex positions with float matrices and
// interpolates z/w in float (lavapipe's depth plane comes from the float positions, not from
// the 1/256-pixel snapped ones it tests coverage with); the worst measured on the city is
// 6.1e-7 of the depth (5 ulps).
double depth_tolerance(const reference::Hit& h) { return 0x1p-18 * h.depth; }

// The pixels the pick test asks about, and why.
struct PickPixel {
  uint32_t x, y;
  const char* kind;
};

// The nearest of the hits that surely cover a pixel centre, if any.
std::optional<reference::Hit> nearest_sure(const std::vector<reference::Hit>& hits) {
  std::optional<reference::Hit> best;
  for (const reference::Hit& h : hits)
    if (h.sure && (!best || h.depth > best->depth)) best = h;
  return best;
}

// A grid (sky included); pixels where two draws cover the centre at clearly different depths (the
// farther at least 25% farther: device depth is znear / distance); pixels on an edge between two
// draws (the neighbour to the right has another nearest draw, and both cover this centre). Each
// kind spread over the image, at most `per_kind`.
std::vector<PickPixel> pick_pixels(const std::vector<std::vector<reference::Hit>>& hits, uint32_t width,
                                   uint32_t height, size_t per_kind) {
  std::vector<PickPixel> grid, overlap, edge;
  for (uint32_t y = 5; y < height; y += 25)
    for (uint32_t x = 7; x < width; x += 39) grid.push_back({x, y, "grid"});
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x + 1 < width; ++x) {
      const auto& here = hits[size_t(y) * width + x];
      const std::optional<reference::Hit> nearest = nearest_sure(here);
      if (!nearest) continue;
      bool farther_draw = false, neighbour_draw_here = false;
      const std::optional<reference::Hit> right = nearest_sure(hits[size_t(y) * width + x + 1]);
      for (const reference::Hit& h : here) {
        farther_draw |= h.sure && h.draw != nearest->draw && h.depth < 0.8 * nearest->depth;
        neighbour_draw_here |= right && h.draw == right->draw;
      }
      if (farther_draw) overlap.push_back({x, y, "overlap"});
      if (right && right->draw != nearest->draw && neighbour_draw_here) edge.push_back({x, y, "edge"});
    }
  EXPECT_GE(overlap.size(), per_kind) << "the city has too few overlapping draws for the test";
  EXPECT_GE(edge.size(), per_kind) << "the city has too few edges between draws for the test";
  std::vector<PickPixel> chosen = grid;
  for (const auto* kind : {&overlap, &edge})
    for (size_t i = 0; i < std::min(per_kind, kind->size()); ++i)
      chosen.push_back((*kind)[i * kind->size() / per_kind]);
  return chosen;
}

// pick against the reference rasteriser: the draw it names covers the pixel centre, and no draw
// that surely covers it is nearer (beyond the depth tolerance); the depth gbuffer.opaque wrote
// there is the named draw's, within that tolerance. Where draws tie within the tolerance
// (coplanar, or the centre on a shared edge) either may be named.
TEST_F(InspectRerunTest, PickNamesTheNearestDrawCoveringThePixel) {
  const FrameRecord& frame = frame0();
  const PassRecord& geometry_pass = pass_named(frame, "gbuffer.opaque");
  const std::vector<uint8_t> draw_bytes = capture_->load(input_named(geometry_pass, "draws.gbuffer.opaque"));
  const auto draws = host_records<GpuDraw>(draw_bytes);
  const auto materials = host_records<GpuMaterial>(capture_->load(input_named(geometry_pass, "scene.materials")));
  const std::vector<uint8_t> geometry = capture_->load(input_named(geometry_pass, "scene.geometry"));
  const std::vector<uint8_t> depth = capture_->load(output_named(geometry_pass, "scene.depth"));
  // Geometry alone decides only where no alpha test cuts holes.
  for (const GpuDraw& d : draws) ASSERT_LT(materials.at(d.material).pbr.z, 0.0f) << "an alpha-tested draw";

  const std::vector<std::vector<reference::Hit>> hits =
      reference::rasterise(reference::screen_triangles(draws, materials, geometry, frame), frame.width, frame.height);
  const std::vector<PickPixel> pixels = pick_pixels(hits, frame.width, frame.height, 6);
  std::string commands;
  for (const PickPixel& p : pixels) commands += "pick " + std::to_string(p.x) + " " + std::to_string(p.y) + " --json; ";
  const Inspected run = inspect(path_, commands);
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), pixels.size());
  size_t covered = 0, sky = 0;
  double worst_depth_error = 0;  // in units of the tolerance
  for (size_t i = 0; i < pixels.size(); ++i) {
    const auto [x, y, kind] = pixels[i];
    const json& j = run.objects[i];
    SCOPED_TRACE(std::string(kind) + " pixel " + std::to_string(x) + "," + std::to_string(y) + ": " + j.dump());
    const std::vector<reference::Hit>& here = hits[size_t(y) * frame.width + x];
    const float written = depth_at(depth, frame.width, x, y);
    if (!j["covered"].get<bool>()) {
      EXPECT_EQ(written, 0.0f) << "pick found no draw where the depth buffer has one";
      EXPECT_FALSE(nearest_sure(here)) << "the reference has a draw there";
      ++sky;
      continue;
    }
    ++covered;
    const uint32_t index = j["draw"];
    ASSERT_LT(index, draws.size());
    const GpuDraw& draw = draws[index];
    EXPECT_EQ(j["instance"], draw.instance);
    EXPECT_EQ(j["material"]["index"], draw.material);
    EXPECT_EQ(j["mesh"]["first_index"], draw.first_index);
    EXPECT_EQ(j["mesh"]["index_count"], draw.index_count);
    EXPECT_EQ(j["stencil"]["value"], draw.stencil);
    // The G-buffer pass writes each draw's stencil value where it draws.
    EXPECT_EQ(stencil_at(depth, frame.width, frame.height, x, y), draw.stencil);
    // The named draw covers the centre at the depth written there.
    std::optional<reference::Hit> named;
    for (const reference::Hit& h : here)
      if (h.draw == index && (!named || std::abs(h.depth - written) < std::abs(named->depth - written))) named = h;
    ASSERT_TRUE(named) << "the draw named does not cover the pixel centre";
    const double error = std::abs(named->depth - written);
    worst_depth_error = std::max(worst_depth_error, error / depth_tolerance(*named));
    EXPECT_LE(error, depth_tolerance(*named)) << "reference depth " << named->depth << ", written " << written;
    // Nothing that surely covers the centre is nearer.
    for (const reference::Hit& h : here) {
      if (!h.sure) continue;
      EXPECT_LE(h.depth, named->depth + depth_tolerance(h) + depth_tolerance(*named))
          << "draw " << h.draw << " is nearer, at depth " << h.depth << "; the named draw's is " << named->depth;
    }
  }
  std::printf("pick: %zu pixels (%zu sky); depth written vs the reference's: worst %.3g of the tolerance\n",
              pixels.size(), sky, worst_depth_error);
  EXPECT_GE(covered, 20u);
  EXPECT_GE(sky, 1u) << "no test pixel on the sky: move the grid";
}

TEST_F(InspectRerunTest, PickOutsideTheOutputIsAnError) {
  const Inspected run = inspect(path_, "pick 320 0; pick 0 0 --json");
  EXPECT_EQ(run.result.code, 2);
  EXPECT_NE(run.result.err.find("outside the 320x180 output"), std::string::npos) << run.result.err;
  EXPECT_EQ(run.objects.size(), 1u) << "the session goes on after the error";
}

TEST_F(InspectRerunTest, HistoryFollowsThePixelPassByPass) {
  const uint32_t x = 160, y = 90;
  const Inspected run = inspect(path_, "history 160 90 --json; help history --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  EXPECT_NE(run.objects.at(1)["summary"].get<std::string>().find("records passes, not draws"), std::string::npos);
  const json& writes = run.objects.at(0)["writes"];
  const FrameRecord& frame = frame0();
  std::map<std::string, size_t> order;
  for (size_t i = 0; i < frame.passes.size(); ++i) order[frame.passes[i].name] = i;
  size_t last = 0;
  bool saw_prepass_depth = false, saw_gbuffer_depth = false, saw_tonemap = false;
  for (const json& w : writes) {
    SCOPED_TRACE(w.dump());
    const std::string pass = w["pass"], resource = w["resource"], status = w["status"];
    ASSERT_TRUE(order.count(pass));
    EXPECT_GE(order[pass], last) << "out of execution order";
    last = order[pass];
    const ResourceRecord& after = output_named(pass_named(frame, pass), resource);
    EXPECT_EQ(w["after"]["hash"], after.hash);
    if (status == "first") {
      EXPECT_TRUE(w["before"].is_null());
    } else if (status == "unchanged") {
      EXPECT_EQ(w["before"]["raw"], w["after"]["raw"]);
    } else {
      EXPECT_EQ(status, "changed");
      EXPECT_NE(w["before"]["raw"], w["after"]["raw"]);
    }
    if (resource == "scene.depth") {
      // Depth and stencil at the pixel, read from the planes of each version.
      const std::vector<uint8_t> raw = capture_->load(after);
      EXPECT_EQ(w["after"]["raw"][0].get<double>(), double(depth_at(raw, 320, x, y)));
      EXPECT_EQ(w["after"]["raw"][1].get<double>(), double(stencil_at(raw, 320, 180, x, y)));
      if (pass == "depth.prepass") {
        saw_prepass_depth = true;
        EXPECT_EQ(status, "first");
      }
      if (pass == "gbuffer.opaque") {
        saw_gbuffer_depth = true;
        const ResourceRecord& before = output_named(pass_named(frame, "depth.prepass"), "scene.depth");
        EXPECT_EQ(w["before"]["hash"], before.hash);
        const std::vector<uint8_t> prior = capture_->load(before);
        const bool same = depth_at(prior, 320, x, y) == depth_at(raw, 320, x, y) &&
                          stencil_at(prior, 320, 180, x, y) == stencil_at(raw, 320, 180, x, y);
        EXPECT_EQ(status, same ? "unchanged" : "changed");
      }
    }
    // bloom.levelK updates mip K of the chain (at half resolution: texel (x/2 >> K, y/2 >> K)).
    if (pass.rfind("bloom.level", 0) == 0 && pass != "bloom.level0" && status != "unchanged") {
      const uint32_t level = uint32_t(std::stoul(pass.substr(11)));
      EXPECT_EQ(w["mip"], level);
      EXPECT_EQ(w["texel"], json::array({(x / 2) >> level, (y / 2) >> level}));
    }
    saw_tonemap |= pass == "tonemap" && resource == "final.ldr";
    EXPECT_NE(resource, "normals.bfn_lut") << "a lookup table is not a screen position";
  }
  EXPECT_TRUE(saw_prepass_depth && saw_gbuffer_depth && saw_tonemap);
}

TEST_F(InspectRerunTest, HistoryOfOneResourceAndErrors) {
  const Inspected run = inspect(path_, "history 10 10 depth.linear --json; history 10 10 no.such; history 400 10");
  EXPECT_EQ(run.result.code, 2);
  ASSERT_EQ(run.objects.size(), 1u);
  const json& writes = run.objects[0]["writes"];
  ASSERT_EQ(writes.size(), 1u);
  EXPECT_EQ(writes[0]["pass"], "depth.convert");
  const std::vector<uint8_t> raw = capture_->load(output_named(pass_named(frame0(), "depth.convert"), "depth.linear"));
  EXPECT_EQ(writes[0]["after"]["raw"][0].get<double>(), double(at<float>(raw, 4 * (10 * 320 + 10))));
  EXPECT_NE(run.result.err.find("writes 'no.such'"), std::string::npos) << run.result.err;
  EXPECT_NE(run.result.err.find("outside the 320x180 output"), std::string::npos) << run.result.err;
}

TEST_F(InspectRerunTest, ReplayJudgesEachOutputByItsContract) {
  const Inspected run = inspect(path_,
                                "goto tonemap --json; replay --json; replay --set exposure=4 --json; "
                                "replay --set no_such=1; goto depth.convert --json; replay --json");
  EXPECT_EQ(run.result.code, 2) << "the unknown parameter fails";
  EXPECT_NE(run.result.err.find("no_such"), std::string::npos) << run.result.err;
  ASSERT_EQ(run.objects.size(), 5u) << run.result.out;
  const json& plain = run.objects[1];
  EXPECT_EQ(plain["pass"], "tonemap");
  ASSERT_EQ(plain["outputs"].size(), 1u);
  EXPECT_TRUE(plain["outputs"][0]["identical"].get<bool>());
  EXPECT_TRUE(plain["outputs"][0]["contract"]["holds"].get<bool>());
  // Four times the exposure moves most of the image by far more than the one code allowed.
  const json& brighter = run.objects[2]["outputs"][0];
  EXPECT_FALSE(brighter["identical"].get<bool>());
  EXPECT_FALSE(brighter["contract"]["holds"].get<bool>());
  EXPECT_GT(brighter["max_abs"].get<double>(), 0.05);
  EXPECT_EQ(run.objects[4]["pass"], "depth.convert");
  for (const json& o : run.objects[4]["outputs"]) EXPECT_TRUE(o["identical"].get<bool>()) << o.dump();
}

TEST_F(InspectRerunTest, ReplayWithAShaderFile) {
  const fs::path dir = scratch("inspect-replay-shader");
  {
    std::ofstream shader(dir / "tonemap.frag");
    shader << "#version 460\nlayout(location = 0) out vec4 colour;\nvoid main() { colour = vec4(1.0); }\n";
  }
  const Inspected run = inspect(path_, "goto tonemap --json; replay --shader " + (dir / "tonemap.frag").string() +
                                           " --json; replay --shader " + (dir / "missing.frag").string());
  EXPECT_EQ(run.result.code, 2);
  EXPECT_NE(run.result.err.find("missing.frag"), std::string::npos) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2u) << run.result.err;
  const json& white = run.objects[1];
  ASSERT_EQ(white["notes"].size(), 1u);
  EXPECT_NE(white["notes"][0].get<std::string>().find("replaces the recorded .frag shader"), std::string::npos);
  EXPECT_FALSE(white["outputs"][0]["identical"].get<bool>());
  EXPECT_FALSE(white["outputs"][0]["contract"]["holds"].get<bool>());
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
