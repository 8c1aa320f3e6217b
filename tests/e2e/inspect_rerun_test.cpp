// The inspect commands that look past one recorded value: `pick` (which draw covers a pixel),
// `history` (a pixel through the frame) and `replay` (the current pass again, with overrides).
// Each is checked against what this file computes from the capture's blobs: triangles projected
// with the recorded camera, stencil and depth planes read by their byte layout.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>

#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
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

// Whether pixel (x, y)'s centre lies in one of the draw's triangles, placed as geometry.glsl
// places them: the position decoded in the draw's box, the draw's model matrix, then the recorded camera's projection ·
// view. The test is in homogeneous coordinates (Olano and Greer, 1997), so triangles that reach behind the camera count
// by their visible part: the centre's ray meets the triangle where weights b solve Σ b_i (x_i − u w_i) = 0 and Σ b_i
// (y_i − v w_i) = 0, i.e. b ∝ r_x × r_y; it is inside when every weight has the sign that puts the point in front (Σ
// b_i w_i > 0).
bool draw_covers(const GpuDraw& draw, const std::vector<uint8_t>& geometry, const FrameRecord& frame, uint32_t x,
                 uint32_t y) {
  const auto header = at<GeometryHeader>(geometry, 0);
  glm::dmat4 view, projection;
  std::memcpy(&view[0][0], frame.camera.view.data(), sizeof(double) * 16);
  std::memcpy(&projection[0][0], frame.camera.projection.data(), sizeof(double) * 16);
  const glm::dmat4 clip_from_object = projection * view * glm::dmat4(draw.model);
  const double u = (x + 0.5) / frame.width * 2 - 1, v = (y + 0.5) / frame.height * 2 - 1;
  for (uint32_t t = 0; t < draw.index_count / 3; ++t) {
    glm::dvec3 rx, ry, w;
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = at<uint32_t>(geometry, header.index_offset + 4 * (draw.first_index + 3 * t + k));
      const Vertex vertex = geometry_vertex(geometry, index + draw.vertex_offset, glm::vec3(draw.position_origin),
                                            glm::vec3(draw.position_step));
      const glm::dvec4 clip =
          clip_from_object * glm::dvec4(vertex.position[0], vertex.position[1], vertex.position[2], 1.0);
      rx[k] = clip.x - u * clip.w;
      ry[k] = clip.y - v * clip.w;
      w[k] = clip.w;
    }
    glm::dvec3 b = glm::cross(rx, ry);
    if (glm::dot(b, w) < 0) b = -b;
    const double slack = 1e-4 * (std::abs(b.x) + std::abs(b.y) + std::abs(b.z));  // ties on shared edges
    if (glm::dot(b, w) > 0 && b.x >= -slack && b.y >= -slack && b.z >= -slack) return true;
  }
  return false;
}

TEST_F(InspectRerunTest, PickNamesTheDrawWhoseTriangleCoversThePixel) {
  const PassRecord& geometry_pass = pass_named(frame0(), "gbuffer.opaque");
  const std::vector<uint8_t> draws = capture_->load(input_named(geometry_pass, "draws.gbuffer.opaque"));
  const std::vector<uint8_t> geometry = capture_->load(input_named(geometry_pass, "scene.geometry"));
  const std::vector<uint8_t> depth = capture_->load(output_named(geometry_pass, "scene.depth"));
  std::vector<std::pair<uint32_t, uint32_t>> pixels;
  std::string commands;
  for (uint32_t y = 5; y < 180; y += 25)
    for (uint32_t x = 7; x < 320; x += 39) {
      pixels.emplace_back(x, y);
      commands += "pick " + std::to_string(x) + " " + std::to_string(y) + " --json; ";
    }
  const Inspected run = inspect(path_, commands);
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), pixels.size());
  size_t covered = 0, sky = 0;
  for (size_t i = 0; i < pixels.size(); ++i) {
    const auto [x, y] = pixels[i];
    const json& j = run.objects[i];
    SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y) + ": " + j.dump());
    if (!j["covered"].get<bool>()) {
      EXPECT_EQ(depth_at(depth, 320, x, y), 0.0f) << "pick found no draw where the depth buffer has one";
      ++sky;
      continue;
    }
    ++covered;
    const uint32_t index = j["draw"];
    ASSERT_LT((index + 1) * sizeof(GpuDraw), draws.size() + 1);
    const auto draw = at<GpuDraw>(draws, index * sizeof(GpuDraw));
    EXPECT_EQ(j["instance"], draw.instance);
    EXPECT_EQ(j["material"]["index"], draw.material);
    EXPECT_EQ(j["mesh"]["first_index"], draw.first_index);
    EXPECT_EQ(j["mesh"]["index_count"], draw.index_count);
    EXPECT_EQ(j["stencil"]["value"], draw.stencil);
    // The G-buffer pass writes each draw's stencil value where it draws.
    EXPECT_EQ(stencil_at(depth, 320, 180, x, y), draw.stencil);
    EXPECT_TRUE(draw_covers(draw, geometry, frame0(), x, y));
  }
  EXPECT_GE(covered, 10u);
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

}  // namespace
}  // namespace nightcap::test
