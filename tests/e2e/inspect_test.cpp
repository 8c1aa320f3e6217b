// `nightcap inspect` in scripted mode, against values decoded here from the capture's raw bytes
// by formulas of this file (bit fields, half floats, znear / depth), never by inspect's decoder.
// (Over 600 lines: one case per inspect command, sharing the capture they inspect.)
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "captures/capture.h"
#include "passes/frame/jitter.h"
#include "passes/sky/atmosphere.glsl.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/inspect_script.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

uint32_t word_at(const std::vector<uint8_t>& raw, uint64_t offset) {
  uint32_t w;
  std::memcpy(&w, raw.data() + offset, 4);
  return w;
}

float float_at(const std::vector<uint8_t>& raw, uint64_t offset) {
  float f;
  std::memcpy(&f, raw.data() + offset, 4);
  return f;
}

// IEEE half to double by its definition: sign, 5-bit exponent (bias 15), 10-bit mantissa.
double half_at(const std::vector<uint8_t>& raw, uint64_t offset) {
  const uint16_t h = uint16_t(raw[offset] | (raw[offset + 1] << 8));
  const int exponent = (h >> 10) & 31, mantissa = h & 1023;
  const double sign = (h & 0x8000) ? -1.0 : 1.0;
  if (exponent == 0) return sign * std::ldexp(mantissa, -24);
  if (exponent == 31) return mantissa ? NAN : sign * INFINITY;
  return sign * std::ldexp(1024 + mantissa, exponent - 25);
}

void expect_unit_vector(const json& actual, double x, double y, double z) {
  const double length = std::sqrt(x * x + y * y + z * z);
  ASSERT_EQ(actual.size(), 3u) << actual;
  EXPECT_NEAR(actual[0].get<double>(), x / length, 1e-6);
  EXPECT_NEAR(actual[1].get<double>(), y / length, 1e-6);
  EXPECT_NEAR(actual[2].get<double>(), z / length, 1e-6);
}

class InspectTest : public CityCaptureTest {};

// Pixels on geometry and sky, and across the screen, so both cleared and drawn texels are read.
const std::vector<std::pair<uint32_t, uint32_t>> kPixels = {{160, 90}, {10, 170}, {300, 20}, {0, 0}, {319, 179}};

std::string pixel_commands(const std::string& resource, const std::string& extra = "") {
  std::string commands;
  for (auto [x, y] : kPixels)
    commands += "; pixel " + std::to_string(x) + " " + std::to_string(y) + " " + resource + extra + " --json";
  return commands;
}

TEST_F(InspectTest, GbufferNormalIsTheUnitVectorOfItsCodes) {
  const ResourceRecord& r = output_named(pass_named(frame0(), "gbuffer.opaque"), "gbuffer.normal");
  const std::vector<uint8_t> raw = capture_->load(r);
  const Inspected run = inspect(path_, "goto gbuffer.opaque --json" + pixel_commands("gbuffer.normal"));
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), kPixels.size() + 1);
  bool drawn = false;
  for (size_t i = 0; i < kPixels.size(); ++i) {
    const json& j = run.objects[i + 1];
    const auto [x, y] = kPixels[i];
    EXPECT_EQ(j["texel"], json::array({x, y}));
    EXPECT_EQ(j["hash"], r.hash);
    const uint32_t w = word_at(raw, 4 * (uint64_t(y) * r.extent.width + x));
    const uint32_t codes[4] = {w & 1023, (w >> 10) & 1023, (w >> 20) & 1023, w >> 30};
    EXPECT_EQ(j["codes"], json::array({codes[0], codes[1], codes[2], codes[3]}));
    const double n[3] = {codes[0] / 1023.0 * 2 - 1, codes[1] / 1023.0 * 2 - 1, codes[2] / 1023.0 * 2 - 1};
    expect_unit_vector(j["decoded"]["normal"], n[0], n[1], n[2]);
    EXPECT_EQ(j["decoded"]["hair"], codes[3] != 0);
    drawn |= std::abs(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0) < 0.01;
  }
  EXPECT_TRUE(drawn) << "no pixel of the test landed on geometry";
}

TEST_F(InspectTest, PackedNormalAndMaterialByChannel) {
  const ResourceRecord& packed = output_named(pass_named(frame0(), "normals.pack"), "normals.packed");
  const ResourceRecord& material = output_named(pass_named(frame0(), "gbuffer.opaque"), "gbuffer.material");
  const std::vector<uint8_t> packed_raw = capture_->load(packed), material_raw = capture_->load(material);
  const Inspected run = inspect(
      path_, "goto normals.pack --json" + pixel_commands("normals.packed") + pixel_commands("gbuffer.material"));
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2 * kPixels.size() + 1);
  for (size_t i = 0; i < kPixels.size(); ++i) {
    const auto [x, y] = kPixels[i];
    const uint64_t at = 4 * (uint64_t(y) * 320 + x);
    const json& p = run.objects[1 + i]["decoded"];
    expect_unit_vector(p["normal"], packed_raw[at] * 2.0 / 255 - 1, packed_raw[at + 1] * 2.0 / 255 - 1,
                       packed_raw[at + 2] * 2.0 / 255 - 1);
    EXPECT_NEAR(p["roughness"].get<double>(), packed_raw[at + 3] / 255.0, 1e-7);
    const json& m = run.objects[1 + kPixels.size() + i]["decoded"];
    EXPECT_NEAR(m["metalness"].get<double>(), material_raw[at] / 255.0, 1e-7);
    EXPECT_NEAR(m["roughness"].get<double>(), material_raw[at + 1] / 255.0, 1e-7);
    EXPECT_NEAR(m["translucency"].get<double>(), material_raw[at + 2] / 255.0, 1e-7);
    EXPECT_NEAR(m["emissive_luminance"].get<double>(), std::pow(2.0, 16.0 * material_raw[at + 3] / 255.0) - 1.0,
                1e-5 * (1 + m["emissive_luminance"].get<double>()));
  }
}

// scene.depth is written by depth.prepass and again by gbuffer.opaque (which adds the stencil):
// each pass shows its own version.
TEST_F(InspectTest, DepthInMetresAndStencilClassOfEachVersion) {
  const double znear = frame0().camera.znear;
  const char* kClasses[][2] = {{"0", "plain"},    {"8", "road"},   {"21", "body"},    {"53", "face"},
                               {"64", "vehicle"}, {"149", "hair"}, {"160", "foliage"}};
  for (const char* pass : {"depth.prepass", "gbuffer.opaque"}) {
    const ResourceRecord& r = output_named(pass_named(frame0(), pass), "scene.depth");
    const std::vector<uint8_t> raw = capture_->load(r);
    const Inspected run = inspect(path_, std::string("goto ") + pass + " --json" + pixel_commands("scene.depth"));
    ASSERT_EQ(run.result.code, 0) << run.result.err;
    ASSERT_EQ(run.objects.size(), kPixels.size() + 1);
    bool sky = false, drawn = false;
    for (size_t i = 0; i < kPixels.size(); ++i) {
      const auto [x, y] = kPixels[i];
      const json& j = run.objects[1 + i];
      EXPECT_EQ(j["hash"], r.hash) << pass;
      const uint64_t index = uint64_t(y) * 320 + x;
      const double device = float_at(raw, 4 * index);
      const uint32_t stencil = raw[320 * 180 * 4 + index];  // the stencil plane follows the depth plane
      EXPECT_EQ(j["decoded"]["device_depth"].get<double>(), device);
      if (device > 0) {
        drawn = true;
        EXPECT_NEAR(j["decoded"]["linear_m"].get<double>(), znear / device, 1e-9 * znear / device);
      } else {
        sky = true;
        EXPECT_TRUE(j["decoded"]["linear_m"].is_string());
      }
      EXPECT_EQ(j["decoded"]["stencil"], stencil);
      std::string name = "unknown";
      for (const auto& c : kClasses)
        if (uint32_t(std::stoi(c[0])) == (stencil & ~2u)) name = c[1];
      EXPECT_EQ(j["decoded"]["class"], name);
      EXPECT_EQ(j["decoded"]["flags"].size(), (stencil & 2u) ? 1u : 0u);
    }
    EXPECT_TRUE(drawn && sky) << pass << ": the pixels should cover geometry and sky";
  }
}

TEST_F(InspectTest, MotionInPixelsAcrossFrames) {
  const Inspected run = inspect(path_, "goto gbuffer.opaque --json; pixel 160 90 gbuffer.motion --frames --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2u);
  const json& frames = run.objects[1]["frames"];
  ASSERT_EQ(frames.size(), 2u);
  bool moving = false;
  for (uint32_t f = 0; f < 2; ++f) {
    const ResourceRecord& r = output_named(pass_named(capture_->frame(f), "gbuffer.opaque"), "gbuffer.motion");
    const std::vector<uint8_t> raw = capture_->load(r);
    const uint64_t at = 4 * (uint64_t(90) * 320 + 160);
    const double u = half_at(raw, at), v = half_at(raw, at + 2);
    EXPECT_EQ(frames[f]["frame"], f);
    EXPECT_EQ(frames[f]["hash"], r.hash);
    EXPECT_EQ(frames[f]["decoded"]["motion_uv"], json::array({u, v}));
    EXPECT_NEAR(frames[f]["decoded"]["motion_pixels"][0].get<double>(), u * 320, 1e-9);
    EXPECT_NEAR(frames[f]["decoded"]["motion_pixels"][1].get<double>(), v * 180, 1e-9);
    moving |= f == 1 && (u != 0 || v != 0);
  }
  EXPECT_TRUE(moving) << "the walking camera should move the centre pixel in frame 1";
}

TEST_F(InspectTest, HdrLuminanceAndHalfResolutionMips) {
  const ResourceRecord& lit = output_named(pass_named(frame0(), "lighting.composite"), "lighting.lit");
  const ResourceRecord& pyramid = output_named(pass_named(frame0(), "depth.pyramid"), "depth.pyramid");
  const std::vector<uint8_t> lit_raw = capture_->load(lit), pyramid_raw = capture_->load(pyramid);
  const Inspected run = inspect(path_,
                                "goto depth.pyramid --json; pixel 300 20 lighting.lit --json; "
                                "pixel 300 20 depth.pyramid --mip 2 --json; pixel 300 20 --mip 9 --json");
  EXPECT_EQ(run.result.code, 2) << "mip 9 does not exist";
  ASSERT_EQ(run.objects.size(), 3u) << run.result.err;
  EXPECT_NE(run.result.err.find("no mip 9"), std::string::npos) << run.result.err;

  const uint64_t at = 8 * (uint64_t(20) * 320 + 300);
  const double r = half_at(lit_raw, at), g = half_at(lit_raw, at + 2), b = half_at(lit_raw, at + 4);
  EXPECT_EQ(run.objects[1]["decoded"]["rgb"], json::array({r, g, b}));
  EXPECT_NEAR(run.objects[1]["decoded"]["luminance"].get<double>(), 0.2126 * r + 0.7152 * g + 0.0722 * b, 1e-12);

  // Mip 2 of a half-resolution pyramid: the texel at (300, 20) · (its size / the output size).
  uint64_t offset = 0;
  uint32_t w = pyramid.extent.width, h = pyramid.extent.height;
  for (int m = 0; m < 2; ++m) {
    offset += uint64_t(w) * h * 8;
    w = std::max(1u, w / 2);
    h = std::max(1u, h / 2);
  }
  const uint32_t tx = 300 * w / 320, ty = 20 * h / 180;
  const json& j = run.objects[2];
  EXPECT_EQ(j["texel"], json::array({tx, ty}));
  EXPECT_EQ(j["mip"], 2);
  const uint64_t texel = offset + 8 * (uint64_t(ty) * w + tx);
  EXPECT_EQ(j["decoded"]["min_m"].get<double>(), float_at(pyramid_raw, texel));
  EXPECT_EQ(j["decoded"]["max_m"].get<double>(), float_at(pyramid_raw, texel + 4));
}

// An 11- or 10-bit unsigned float of B10G11R11 by its definition: 5-bit exponent (bias 15) over a
// `mantissa_bits` mantissa.
double small_float(uint32_t bits, int mantissa_bits) {
  const uint32_t exponent = bits >> mantissa_bits, mantissa = bits & ((1u << mantissa_bits) - 1);
  if (exponent == 0) return std::ldexp(mantissa, -14 - mantissa_bits);
  return std::ldexp((1u << mantissa_bits) + mantissa, int(exponent) - 15 - mantissa_bits);
}

TEST_F(InspectTest, CubeMapTexelAlongADirection) {
  const ResourceRecord& cube = output_named(pass_named(frame0(), "sky.cubemap"), "sky.cubemap");
  const ResourceRecord& specular = output_named(pass_named(frame0(), "sky.specular"), "sky.specular");
  const Inspected run = inspect(path_,
                                "goto sky.specular --json; direction 0 -1 0.3 sky.cubemap --json; "
                                "direction 1 0.2 -0.1 --mip 3 --json; direction 0 0 0 sky.cubemap --json");
  EXPECT_EQ(run.result.code, 2) << "a zero direction looks nowhere";
  ASSERT_EQ(run.objects.size(), 3u) << run.result.err;
  EXPECT_NE(run.result.err.find("not zero"), std::string::npos) << run.result.err;

  // (0, −1, 0.3): −Y is the major axis, face 3; s = (x / 1 + 1) / 2 = 0.5, t = (−z / 1 + 1) / 2 = 0.35.
  const json& down = run.objects[1];
  EXPECT_EQ(down["face"], "-Y");
  EXPECT_EQ(down["layer"], 3);
  const uint32_t side = cube.extent.width, x = side / 2, y = uint32_t(0.35 * side);
  EXPECT_EQ(down["texel"], json::array({x, y}));
  const uint32_t word = word_at(capture_->load(cube), 4 * (uint64_t(3) * side * side + uint64_t(y) * side + x));
  EXPECT_EQ(down["decoded"]["rgb"], json::array({small_float(word & 0x7FF, 6), small_float((word >> 11) & 0x7FF, 6),
                                                 small_float(word >> 22, 5)}));

  // (1, 0.2, −0.1) at mip 3 of the current pass's output: +X, face 0; s = (0.1 + 1) / 2, t = (−0.2 + 1) / 2.
  const json& side_texel = run.objects[2];
  EXPECT_EQ(side_texel["face"], "+X");
  const uint32_t base = specular.extent.width, at_mip = base >> 3;
  const uint32_t sx = uint32_t(0.55 * at_mip), sy = uint32_t(0.4 * at_mip);
  EXPECT_EQ(side_texel["texel"], json::array({sx, sy}));
  EXPECT_EQ(side_texel["mip"], 3);
  uint64_t offset = 0;
  for (uint32_t m = 0; m < 3; ++m) offset += uint64_t(base >> m) * (base >> m) * 8 * 6;
  offset += 8 * (uint64_t(sy) * at_mip + sx);
  const std::vector<uint8_t> raw = capture_->load(specular);
  EXPECT_EQ(side_texel["decoded"]["rgb"],
            json::array({half_at(raw, offset), half_at(raw, offset + 2), half_at(raw, offset + 4)}));
}

// TAA at a pixel of frame 1 (the first with history): taa.history's frames (its alpha) and the
// weight the history had in the resolve, 1 − 1/frames; taa.resolved's clip (its alpha), and
// whether clipping moved the history; the frame's jitter in the camera view of frame.views.
TEST_F(InspectTest, TaaHistoryWeightClipAndTheFramesJitter) {
  const PassRecord& taa = pass_named(capture_->frame(1), "taa");
  const std::vector<uint8_t> history = capture_->load(output_named(taa, "taa.history"));
  const std::vector<uint8_t> resolved = capture_->load(output_named(taa, "taa.resolved"));
  const Inspected run = inspect(path_, "frame 1 --json; goto taa --json" + pixel_commands("taa.history") +
                                           pixel_commands("taa.resolved") + "; buffer frame.views --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2 * kPixels.size() + 3);
  for (size_t i = 0; i < kPixels.size(); ++i) {
    const auto [x, y] = kPixels[i];
    const uint64_t texel = 8 * (uint64_t(y) * 320 + x);
    const double frames = half_at(history, texel + 6), clip = half_at(resolved, texel + 6);
    const json& h = run.objects[2 + i]["decoded"];
    EXPECT_EQ(h["frames"].get<double>(), frames);
    EXPECT_GE(frames, 1.0);
    EXPECT_LE(frames, 2.0) << "frame 1 averages two frames at most";
    EXPECT_DOUBLE_EQ(h["history_weight"].get<double>(), 1.0 - 1.0 / frames);
    const json& r = run.objects[2 + kPixels.size() + i]["decoded"];
    EXPECT_EQ(r["clip_removed"].get<double>(), clip);
    EXPECT_EQ(r["history_clipped"].get<bool>(), clip > 0.0);
    EXPECT_EQ(r["rgb"][0].get<double>(), half_at(history, texel)) << "the resolved colour is the history's";
  }
  // Frame 1's jitter (passes/frame/jitter.h), in pixels and in uv units.
  const glm::dvec2 jitter = taa_jitter(1);
  const json& recorded = run.objects.back()["values"][0]["fields"]["jitter"];
  ASSERT_EQ(recorded.size(), 4u) << run.objects.back();
  const float expected[4] = {float(jitter.x), float(jitter.y), float(jitter.x / 320), float(jitter.y / 180)};
  for (int c = 0; c < 4; ++c) EXPECT_EQ(recorded[c].get<float>(), expected[c]) << c;
}

// The GI volume's cell under a pixel at a slice: its 27 coefficients gathered from the 7 blocks of
// slices (volume_layout.glsl.h: four to a texel, coefficient-major, block k at slice z + 64k),
// decoded here from the raw halves, and the irradiance about each axis from the real spherical
// harmonics' definitions (Y00 = √(1/4π), Y1m = √(3/4π) × the axis, Y20 and Y22's zonal parts).
TEST_F(InspectTest, GiVolumeCellAndItsIrradianceAboutEachAxis) {
  const ResourceRecord& volume = output_named(pass_named(frame0(), "gi.volume"), "gi.volume");
  const Inspected run = inspect(path_,
                                "goto gi.volume --json; pixel 160 90 gi.volume --slice 20 --json; "
                                "pixel 160 90 gi.volume --slice 64 --json");
  EXPECT_EQ(run.result.code, 2) << "slice 64 is past the 64 cells along z";
  ASSERT_EQ(run.objects.size(), 2u) << run.result.err;
  EXPECT_NE(run.result.err.find("past its 64 cells"), std::string::npos) << run.result.err;
  const json& cell = run.objects[1];
  const uint32_t cells = volume.extent.width, x = 160 * cells / 320, y = 90 * cells / 180;
  ASSERT_EQ(volume.extent.depth, 7 * cells);
  EXPECT_EQ(cell["texel"], json::array({x, y}));
  const std::vector<uint8_t> raw = capture_->load(volume);
  double c[28];
  for (uint32_t k = 0; k < 7; ++k)
    for (uint32_t m = 0; m < 4; ++m)
      c[4 * k + m] = half_at(raw, 8 * ((uint64_t(20 + k * cells) * cells + y) * cells + x) + 2 * m);
  const json& coefficients = cell["decoded"]["coefficients"];
  ASSERT_EQ(coefficients.size(), 9u);
  for (int i = 0; i < 9; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(coefficients[i][k].get<double>(), c[3 * i + k]) << i;
  const double pi = 3.14159265358979323846;
  const double y00 = std::sqrt(1 / (4 * pi)), y1 = std::sqrt(3 / (4 * pi)), y20 = std::sqrt(5 / (16 * pi)),
               y22 = std::sqrt(15 / (16 * pi));
  // About +y: Y1−1 = y1, Y20 = −y20 (3z² − 1 at z = 0), Y22 = −y22 (x² − y²); about −z: Y10 = −y1, Y20 = 2 y20.
  for (int k = 0; k < 3; ++k) {
    const double up = c[k] * y00 + c[3 + k] * y1 - c[18 + k] * y20 - c[24 + k] * y22;
    const double back = c[k] * y00 - c[6 + k] * y1 + 2 * c[18 + k] * y20;
    EXPECT_NEAR(cell["decoded"]["irradiance_over_pi"]["+y"][k].get<double>(), std::max(up, 0.0),
                1e-6 * std::abs(up) + 1e-9);
    EXPECT_NEAR(cell["decoded"]["irradiance_over_pi"]["-z"][k].get<double>(), std::max(back, 0.0),
                1e-6 * std::abs(back) + 1e-9);
  }
  EXPECT_EQ(cell["decoded"]["cell_metres"], 2.0);
}

// sky.view by direction: straight up is its first texel (zenith, and no azimuth: u = 0), straight
// down its last row's first, level and away from the light (the way it travels) its last column,
// above the horizon's row; each decoded as the texel the capture holds there.
TEST_F(InspectTest, SkyViewTexelAlongADirection) {
  const ResourceRecord& view = output_named(pass_named(frame0(), "sky.view"), "sky.view");
  const ResourceRecord& record = output_named(pass_named(frame0(), "sky.atmosphere"), "sky.atmosphere");
  GpuAtmosphere atmosphere;
  const std::vector<uint8_t> bytes = capture_->load(record);
  ASSERT_EQ(bytes.size(), sizeof atmosphere);
  std::memcpy(&atmosphere, bytes.data(), sizeof atmosphere);
  const std::string away = std::to_string(atmosphere.light.x) + " 0 " + std::to_string(atmosphere.light.z);
  const Inspected run =
      inspect(path_, "goto sky.view --json; direction 0 1 0 --json; direction 0 -1 0 --json; direction " + away +
                         " --json; goto sky.transmittance --json; direction 0 1 0 --json");
  EXPECT_EQ(run.result.code, 2) << "the transmittance LUT is not looked up by a world direction";
  EXPECT_NE(run.result.err.find("neither a cube map nor"), std::string::npos) << run.result.err;
  ASSERT_EQ(run.objects.size(), 5u) << run.result.err;
  const uint32_t w = view.extent.width, h = view.extent.height;
  EXPECT_EQ(run.objects[1]["texel"], json::array({0, 0}));
  EXPECT_EQ(run.objects[2]["texel"], json::array({0, h - 1}));
  EXPECT_EQ(run.objects[3]["texel"][0], w - 1);
  EXPECT_LT(run.objects[3]["texel"][1], h / 2) << "level is above the horizon seen from the street";
  const std::vector<uint8_t> raw = capture_->load(view);
  for (int i = 1; i <= 3; ++i) {
    const uint64_t x = run.objects[i]["texel"][0], y = run.objects[i]["texel"][1];
    const uint64_t offset = 8 * (y * w + x);
    EXPECT_EQ(run.objects[i]["decoded"]["rgb"],
              json::array({half_at(raw, offset), half_at(raw, offset + 2), half_at(raw, offset + 4)}))
        << run.objects[i].dump();
  }
}

TEST_F(InspectTest, NavigationInfoPipelineAndShader) {
  const std::vector<PassRecord>& passes = frame0().passes;
  size_t gbuffer = 0;
  while (passes[gbuffer].name != "gbuffer.opaque") ++gbuffer;
  const Inspected run =
      inspect(path_,
              "passes --json; goto gbuffer.opaque --json; next --json; prev --json; info --json; "
              "pipeline --json; shader opaque.frag --json; frame 1 --json; goto depth.convert --json; "
              "info --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 10u);
  ASSERT_EQ(run.objects[0]["passes"].size(), passes.size());
  for (size_t i = 0; i < passes.size(); ++i) {
    EXPECT_EQ(run.objects[0]["passes"][i]["name"], passes[i].name);
    EXPECT_EQ(run.objects[0]["passes"][i]["status"], passes[i].ran ? "ran" : "skipped");
  }
  EXPECT_EQ(run.objects[1]["pass"], "gbuffer.opaque");
  EXPECT_EQ(run.objects[2]["pass"], passes[gbuffer + 1].name);
  EXPECT_EQ(run.objects[3]["pass"], "gbuffer.opaque");

  const json& info = run.objects[4];
  ASSERT_EQ(info["outputs"].size(), passes[gbuffer].outputs.size());
  for (size_t i = 0; i < passes[gbuffer].outputs.size(); ++i) {
    const ResourceRecord& r = passes[gbuffer].outputs[i];
    EXPECT_EQ(info["outputs"][i]["resource"], r.resource);
    EXPECT_EQ(info["outputs"][i]["hash"], r.hash);
    EXPECT_EQ(info["outputs"][i]["format"], format_info(r.format)->name);
    EXPECT_EQ(info["outputs"][i]["width"], r.extent.width);
    EXPECT_EQ(info["outputs"][i]["contract"]["kind"], contract_kind_name(r.contract.kind));
  }
  EXPECT_EQ(info["inputs"].size(), passes[gbuffer].inputs.size());

  EXPECT_EQ(run.objects[5]["pipelines"], passes[gbuffer].pipelines);
  EXPECT_EQ(run.objects[5]["samplers"], passes[gbuffer].samplers);

  const json& shader = run.objects[6]["shaders"];
  ASSERT_EQ(shader.size(), 1u);
  const ShaderRecord* frag = nullptr;
  for (const ShaderRecord& s : passes[gbuffer].shaders)
    if (s.path == "gbuffer/opaque.frag") frag = &s;
  ASSERT_NE(frag, nullptr);
  EXPECT_EQ(shader[0]["glsl"], capture_->load_shader_source(*frag));
  EXPECT_NE(shader[0]["spirv"].get<std::string>().find("OpEntryPoint Fragment"), std::string::npos);

  EXPECT_EQ(run.objects[7]["frame"], 1);
  EXPECT_EQ(run.objects[7]["pass"], "gbuffer.opaque") << "changing frame keeps the pass";
  const PassRecord& convert = pass_named(capture_->frame(1), "depth.convert");
  EXPECT_EQ(run.objects[9]["frame"], 1);
  EXPECT_EQ(run.objects[9]["outputs"][0]["hash"], convert.outputs[0].hash);
  EXPECT_EQ(run.objects[9]["outputs"][0]["contract"]["kind"], "linear_depth");
  EXPECT_EQ(run.objects[9]["outputs"][0]["contract"]["description"], contract_description(convert.outputs[0].contract));
}

TEST_F(InspectTest, BufferBySchemaAndAsWords) {
  const PassRecord& cull = pass_named(frame0(), "cull.main");
  const ResourceRecord& draws = output_named(cull, "draws.gbuffer.opaque");
  ASSERT_TRUE(draws.schema.has_value());
  const std::vector<uint8_t> draws_raw = capture_->load(draws);
  const ResourceRecord& histogram = output_named(pass_named(frame0(), "exposure"), "exposure.histogram");
  ASSERT_FALSE(histogram.schema.has_value());
  const std::vector<uint8_t> histogram_raw = capture_->load(histogram);
  // Offsets from the manifest's schema JSON, read here field by field.
  const json manifest = read_json(path_ / "manifest.json");
  json schema;
  for (const json& p : manifest["frames"][0]["passes"])
    if (p["name"] == "cull.main")
      for (const json& o : p["outputs"])
        if (o["resource"] == "draws.gbuffer.opaque") schema = o["schema"];
  const uint32_t stride = schema["stride"];
  const uint64_t element = draws_raw.size() / stride - 1;
  const Inspected run =
      inspect(path_, "goto tonemap --json; buffer draws.gbuffer.opaque --element " + std::to_string(element) +
                         " --json; buffer exposure.histogram --json; "
                         "buffer exposure.histogram --element 100000 --json");
  EXPECT_EQ(run.result.code, 2);
  ASSERT_EQ(run.objects.size(), 3u) << run.result.err;
  const json& fields = run.objects[1]["values"][0]["fields"];
  for (const json& field : schema["fields"]) {
    const std::string name = field["name"], type = field["type"];
    const uint64_t offset = element * stride + field["offset"].get<uint64_t>();
    if (type == "u32") {
      EXPECT_EQ(fields[name].get<double>(), word_at(draws_raw, offset)) << name;
    } else if (type == "mat4") {
      for (int c = 0; c < 16; ++c)
        EXPECT_EQ(fields[name][c].get<double>(), float_at(draws_raw, offset + 4 * c)) << name;
    }
  }
  const json& words = run.objects[2]["words"];
  ASSERT_EQ(words.size(), histogram_raw.size() / 4);
  for (size_t i = 0; i < words.size(); ++i) EXPECT_EQ(words[i]["u32"], word_at(histogram_raw, 4 * i));
}

TEST_F(InspectTest, StatsOfLinearDepth) {
  const ResourceRecord& r = output_named(pass_named(frame0(), "depth.convert"), "depth.linear");
  const std::vector<uint8_t> raw = capture_->load(r);
  const Inspected run = inspect(path_, "stats depth.linear --json; stats depth.linear --rect 100 50 40 30 --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2u);
  struct Rect {
    uint32_t x, y, w, h;
  };
  const Rect rects[2] = {{0, 0, 320, 180}, {100, 50, 40, 30}};
  for (int k = 0; k < 2; ++k) {
    double lo = INFINITY, hi = -INFINITY, sum = 0;
    uint64_t count = 0, denormal = 0;
    for (uint32_t y = rects[k].y; y < rects[k].y + rects[k].h; ++y)
      for (uint32_t x = rects[k].x; x < rects[k].x + rects[k].w; ++x) {
        const float v = float_at(raw, 4 * (uint64_t(y) * 320 + x));
        lo = std::min(lo, double(v));
        hi = std::max(hi, double(v));
        sum += v;
        ++count;
        denormal += std::fpclassify(v) == FP_SUBNORMAL;
      }
    const json& c = run.objects[k]["channels"][0];
    EXPECT_EQ(c["min"].get<double>(), lo);
    EXPECT_EQ(c["max"].get<double>(), hi);
    EXPECT_NEAR(c["mean"].get<double>(), sum / count, 1e-9 * std::abs(sum / count));
    EXPECT_EQ(c["finite"], count);
    EXPECT_EQ(c["nan"], 0);
    EXPECT_EQ(c["inf"], 0);
    EXPECT_EQ(c["denormal"], denormal);
    uint64_t binned = 0;
    for (const json& bin : c["histogram"]) binned += bin.get<uint64_t>();
    EXPECT_EQ(binned, count);
  }
}

// lights.clusters under a pixel: the froxel of the pixel's tile (`tile` pixels on a side) at the
// slice its depth.linear falls in (`slices` slices, exponential from znear to 2000 m, the last one
// to infinity), or at --slice, and the light indices its (offset, count) select in
// lights.cluster_indices.
void expect_froxels_decoded(const std::filesystem::path& path, const Capture& capture, uint32_t tile, uint32_t slices) {
  const FrameRecord& frame = capture.frame(0);
  const PassRecord& pass = pass_named(frame, "lights.cluster");
  const std::vector<uint8_t> clusters = capture.load(output_named(pass, "lights.clusters"));
  const std::vector<uint8_t> indices = capture.load(output_named(pass, "lights.cluster_indices"));
  const std::vector<uint8_t> linear = capture.load(output_named(pass_named(frame, "depth.convert"), "depth.linear"));
  const double znear = frame.camera.znear, far = std::max(2000.0, 2 * znear);
  const uint32_t tiles_x = (320 + tile - 1) / tile, tiles_y = (180 + tile - 1) / tile;
  const uint32_t last = slices - 1;
  const Inspected run =
      inspect(path, "goto lights.cluster --json" + pixel_commands("lights.clusters") +
                        "; pixel 100 100 lights.clusters --slice " + std::to_string(last) + " --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), kPixels.size() + 2);
  auto list_at = [&](uint32_t tx, uint32_t ty, uint32_t slice) {
    const uint64_t texel = (uint64_t(slice) * tiles_y + ty) * tiles_x + tx;
    const uint32_t offset = word_at(clusters, 8 * texel), count = word_at(clusters, 8 * texel + 4);
    std::vector<uint32_t> lights;
    for (uint32_t k = 0; k < count; ++k) lights.push_back(word_at(indices, 4 * (uint64_t(offset) + k)));
    return lights;
  };
  bool some_light = false;
  for (size_t i = 0; i < kPixels.size(); ++i) {
    const auto [x, y] = kPixels[i];
    const json& d = run.objects[1 + i]["decoded"];
    const double depth = float_at(linear, 4 * (uint64_t(y) * 320 + x));
    const double k = std::floor(std::log2(depth / znear) / std::log2(far / znear) * slices);
    const uint32_t slice = uint32_t(std::clamp(k, 0.0, double(last)));
    EXPECT_EQ(d["depth_m"].get<double>(), depth);
    EXPECT_EQ(d["froxel"], json::array({x / tile, y / tile, slice})) << x << "," << y;
    const std::vector<uint32_t> expected = list_at(x / tile, y / tile, slice);
    EXPECT_EQ(d["lights"].get<std::vector<uint32_t>>(), expected) << x << "," << y;
    EXPECT_EQ(d["count"], expected.size());
    some_light = some_light || !expected.empty();
  }
  EXPECT_TRUE(some_light) << "the pixels should fall in a lit froxel";
  const json& sliced = run.objects.back()["decoded"];
  EXPECT_EQ(sliced["froxel"], json::array({100 / tile, 100 / tile, last}));
  EXPECT_FALSE(sliced.contains("depth_m"));
  EXPECT_EQ(sliced["lights"].get<std::vector<uint32_t>>(), list_at(100 / tile, 100 / tile, last));
}

TEST_F(InspectTest, FroxelUnderAPixelAndItsLightList) { expect_froxels_decoded(path_, *capture_, 32, 64); }

// A capture of another froxel shape: inspect finds a pixel's froxel from what the capture
// recorded, and (what inspect shows must be what replay reproduces) every pass replays it
// bit-identically, lights.cluster and lighting.tiled from their recorded inputs included.
TEST(InspectOtherFroxelShape, FroxelUnderAPixelAndItsLightList) {
  const std::filesystem::path path = shared_capture("city-froxels-16x32", kCityOtherFroxels);
  expect_froxels_decoded(path, Capture::open(path), 16, 32);
}

TEST(InspectOtherFroxelShape, ReplaysBitIdentically) {
  const std::filesystem::path path = shared_capture("city-froxels-16x32", kCityOtherFroxels);
  for (int frame : {0, 1}) {
    const CliResult r = run_cli("replay --verify --json --frame " + std::to_string(frame) + " " + quote(path));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const json report = json::parse(r.out);
    std::set<std::string> replayed;
    for (const auto& p : report.at("passes")) {
      if (!p.at("replayed")) continue;
      replayed.insert(p.at("name").get<std::string>());
      for (const auto& o : p.at("outputs"))
        EXPECT_EQ(o.at("verdict"), "identical") << p.at("name") << " " << o.at("resource");
    }
    EXPECT_TRUE(replayed.count("lights.cluster") && replayed.count("lighting.tiled")) << "frame " << frame;
  }
}

// Half-float denormals counted from the stored bits: the first frame's motion is tiny noise, much
// of it below the smallest normal half.
TEST_F(InspectTest, StatsCountStoredHalfDenormals) {
  const ResourceRecord& r = output_named(pass_named(frame0(), "gbuffer.opaque"), "gbuffer.motion");
  const std::vector<uint8_t> raw = capture_->load(r);
  const Inspected run = inspect(path_, "stats gbuffer.motion --json");
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  ASSERT_EQ(run.objects.size(), 1u);
  for (int channel = 0; channel < 2; ++channel) {
    uint64_t denormal = 0;
    for (uint64_t i = 0; i < 320 * 180; ++i) {
      const uint16_t bits = uint16_t(raw[4 * i + 2 * channel] | (raw[4 * i + 2 * channel + 1] << 8));
      denormal += (bits & 0x7c00) == 0 && (bits & 0x3ff) != 0;
    }
    EXPECT_GT(denormal, 0u) << "the test needs denormals to count";
    EXPECT_EQ(run.objects[0]["channels"][channel]["denormal"], denormal) << channel;
  }
}

// A pixel reads the one blob it decodes: with every other blob made unreadable it still answers,
// and a command needing a damaged blob fails alone, naming the file.
TEST_F(InspectTest, ReadsOnlyTheBlobItDecodes) {
  const fs::path copy = scratch("damaged") / "capture";
  fs::copy(path_, copy, fs::copy_options::recursive);
  const ResourceRecord& normal = output_named(pass_named(frame0(), "gbuffer.opaque"), "gbuffer.normal");
  const ResourceRecord& material = output_named(pass_named(frame0(), "gbuffer.opaque"), "gbuffer.material");
  for (const auto& entry : fs::directory_iterator(copy / "blobs"))
    if (entry.path().filename() != fs::path(normal.blob).filename())
      std::ofstream(entry.path(), std::ios::binary | std::ios::trunc) << "damaged";
  const Inspected run = inspect(copy,
                                "passes --json; pixel 160 90 gbuffer.normal --json; pixel 160 90 "
                                "gbuffer.material --json; info --json");
  EXPECT_EQ(run.result.code, 2);
  ASSERT_EQ(run.objects.size(), 3u) << run.result.err;
  EXPECT_EQ(run.objects[1]["hash"], normal.hash);
  EXPECT_NE(run.result.err.find(fs::path(material.blob).filename().string()), std::string::npos) << run.result.err;
}

TEST_F(InspectTest, ErrorsAreOneLineAndTheSessionGoesOn) {
  const Inspected run =
      inspect(path_,
              "goto no.such.pass; pixel 320 0 gbuffer.normal; pixel 1 1 no.such.resource; frobnicate; "
              "goto tonemap --json");
  EXPECT_EQ(run.result.code, 2);
  ASSERT_EQ(run.objects.size(), 1u) << run.result.out;
  EXPECT_EQ(run.objects[0]["pass"], "tonemap");
  std::istringstream lines(run.result.err);
  std::vector<std::string> errors;
  for (std::string line; std::getline(lines, line);) errors.push_back(line);
  ASSERT_EQ(errors.size(), 4u) << run.result.err;
  EXPECT_NE(errors[0].find("no pass 'no.such.pass'"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("outside the 320x180 output"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find("no resource 'no.such.resource'"), std::string::npos) << errors[2];
  EXPECT_NE(errors[3].find("unknown command 'frobnicate'"), std::string::npos) << errors[3];

  const CliResult fine = run_cli("inspect " + quote(path_) + " -c 'goto tonemap; pixel 1 1'");
  EXPECT_EQ(fine.code, 0) << fine.err;
  EXPECT_NE(fine.out.find("final.ldr (colour, R8G8B8A8_SRGB) frame 0 texel (1, 1)"), std::string::npos) << fine.out;
}

TEST_F(InspectTest, ScriptFileHelpAndUsage) {
  const fs::path script = scratch("script") / "commands.txt";
  std::ofstream(script) << "# a comment\ngoto tonemap --json\n\nhelp --json; help pixel --json\nquit --json\n"
                        << "goto depth.convert --json\n";
  const CliResult run = run_cli("inspect " + quote(path_) + " --script " + quote(script));
  ASSERT_EQ(run.code, 0) << run.err;
  std::istringstream lines(run.out);
  std::vector<json> objects;
  for (std::string line; std::getline(lines, line);) objects.push_back(json::parse(line));
  ASSERT_EQ(objects.size(), 4u) << "nothing runs after quit";
  EXPECT_EQ(objects[0]["pass"], "tonemap");
  EXPECT_EQ(objects[3]["quit"], true);
  std::set<std::string> commands;
  for (const json& c : objects[1]["commands"]) commands.insert(c["name"]);
  for (const char* name : {"passes", "goto", "next", "prev", "frame", "info", "pipeline", "shader", "pixel", "buffer",
                           "stats", "help", "quit"})
    EXPECT_TRUE(commands.count(name)) << name;
  EXPECT_EQ(objects[2]["name"], "pixel");

  const CliResult help = run_cli("inspect --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("pixel X Y [RESOURCE]"), std::string::npos) << help.out;
}

// Every channel of a file as float, read by OpenImageIO (not nightcap's code).
std::vector<float> read_image(const fs::path& file, int& width, int& height, int& channels,
                              std::vector<std::string>* names = nullptr) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  channels = spec.nchannels;
  if (names) *names = spec.channelnames;
  std::vector<float> pixels(size_t(width) * height * channels);
  in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data());
  return pixels;
}

// The cluster heat map: each tile's longest list over its slices, read back from the PNG by
// OpenImageIO and matched to the lengths decoded here from the lights.clusters blob, through the
// colour scale the help describes (dark blue for one light, white for the longest, black empty).
TEST_F(InspectTest, ClusterHeatMapShowsEachTilesLongestList) {
  const PassRecord& pass = pass_named(frame0(), "lights.cluster");
  const std::vector<uint8_t> clusters = capture_->load(output_named(pass, "lights.clusters"));
  const uint32_t tiles_x = (320 + 31) / 32, tiles_y = (180 + 31) / 32;
  std::vector<uint32_t> longest(tiles_x * tiles_y, 0), at_slice(tiles_x * tiles_y, 0);
  for (uint32_t slice = 0; slice < 64; ++slice)
    for (uint32_t t = 0; t < tiles_x * tiles_y; ++t) {
      const uint32_t count = word_at(clusters, 8 * (uint64_t(slice) * tiles_x * tiles_y + t) + 4);
      longest[t] = std::max(longest[t], count);
      if (slice == 20) at_slice[t] = count;
    }
  const uint32_t top = *std::max_element(longest.begin(), longest.end());
  ASSERT_GT(top, 1u) << "the test needs lists of different lengths";
  const fs::path dir = scratch("heatmap");
  const Inspected run =
      inspect(path_, "export lights.clusters --heatmap -o " + (dir / "all.png").string() +
                         " --json; export lights.clusters --heatmap --slice 20 -o " + (dir / "slice.png").string() +
                         " --json; export gbuffer.normal --heatmap -o " + (dir / "no.png").string());
  EXPECT_EQ(run.result.code, 2) << "a G-buffer target has no lists";
  EXPECT_NE(run.result.err.find("gbuffer.normal holds no lists"), std::string::npos) << run.result.err;
  ASSERT_EQ(run.objects.size(), 2u) << run.result.err;
  EXPECT_EQ(run.objects[0]["longest"], top);
  // --json's mean is over the tiles with a list (0 for a slice without any), of the lengths the map
  // draws.
  for (const auto& [object, lengths] : {std::pair{run.objects[0], longest}, {run.objects[1], at_slice}}) {
    uint64_t sum = 0, tiles = 0;
    for (uint32_t length : lengths) {
      sum += length;
      tiles += length > 0;
    }
    EXPECT_DOUBLE_EQ(object["mean"].get<double>(), tiles ? double(sum) / double(tiles) : 0.0) << object;
    EXPECT_EQ(object["longest"], *std::max_element(lengths.begin(), lengths.end()));
  }
  for (const auto& [file, lengths] : {std::pair{dir / "all.png", longest}, {dir / "slice.png", at_slice}}) {
    int width = 0, height = 0, channels = 0;
    const std::vector<float> pixels = read_image(file, width, height, channels);
    ASSERT_EQ(width, int(tiles_x * 32)) << file;
    ASSERT_EQ(height, int(tiles_y * 32)) << file;
    const uint32_t file_top = *std::max_element(lengths.begin(), lengths.end());
    for (uint32_t t = 0; t < tiles_x * tiles_y; ++t) {
      // The centre of the tile's block, and the scale's stops at its ends.
      const size_t i = (size_t((t / tiles_x) * 32 + 16) * width + (t % tiles_x) * 32 + 16) * channels;
      const int r = int(std::lround(pixels[i] * 255)), g = int(std::lround(pixels[i + 1] * 255)),
                b = int(std::lround(pixels[i + 2] * 255));
      if (lengths[t] == 0) {
        EXPECT_EQ(r + g + b, 0) << file << " tile " << t;
      } else if (lengths[t] == file_top) {
        EXPECT_EQ(r + g + b, 3 * 255) << file << " tile " << t;
      } else if (lengths[t] == 1) {
        EXPECT_EQ(std::vector<int>({r, g, b}), std::vector<int>({26, 26, 140})) << file << " tile " << t;
      } else {
        EXPECT_GT(r + g + b, 0) << file << " tile " << t;
      }
    }
  }
}

TEST_F(InspectTest, ExportValuesAndPictures) {
  const fs::path dir = scratch("export");
  const Inspected run =
      inspect(path_, "goto gbuffer.opaque --json; export gbuffer.opaque --all -o " + dir.string() +
                         "/all --json; export depth.pyramid --mip 1 -o " + dir.string() +
                         "/pyramid.exr --json; export scene.depth --stencil -o " + dir.string() +
                         "/stencil.png --json; export lighting.lit -o " + dir.string() +
                         "/lit.png --json; export gbuffer.normal -o " + dir.string() + "/normal.tiff --json");
  EXPECT_EQ(run.result.code, 2) << "a .tiff is refused";
  ASSERT_EQ(run.objects.size(), 5u) << run.result.err;
  const PassRecord& gbuffer = pass_named(frame0(), "gbuffer.opaque");
  std::set<std::string> written;
  for (const json& f : run.objects[1]["files"]) written.insert(fs::path(f.get<std::string>()).filename().string());
  for (const ResourceRecord& r : gbuffer.outputs) {
    EXPECT_TRUE(written.count(r.resource + ".exr") && written.count(r.resource + ".png")) << r.resource;
    EXPECT_TRUE(fs::exists(dir / "all" / (r.resource + ".png"))) << r.resource;
  }
  EXPECT_TRUE(written.count("scene.depth.stencil.png"));

  // Normals as colour: 0.5·n + 0.5 of the unit vector of the codes.
  const ResourceRecord& normal = output_named(gbuffer, "gbuffer.normal");
  const std::vector<uint8_t> normal_raw = capture_->load(normal);
  int w = 0, h = 0, c = 0;
  const std::vector<float> png = read_image(dir / "all" / "gbuffer.normal.png", w, h, c);
  ASSERT_EQ(w, 320);
  ASSERT_EQ(h, 180);
  for (auto [x, y] : kPixels) {
    const uint32_t word = word_at(normal_raw, 4 * (uint64_t(y) * 320 + x));
    double n[3] = {(word & 1023) / 1023.0 * 2 - 1, ((word >> 10) & 1023) / 1023.0 * 2 - 1,
                   ((word >> 20) & 1023) / 1023.0 * 2 - 1};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(png[(size_t(y) * w + x) * c + k] * 255.0, std::round((0.5 * n[k] / length + 0.5) * 255), 1.0001)
          << x << "," << y;
  }

  // Real values: the albedo's 10-bit codes / 1023, the depth as stored.
  const ResourceRecord& depth = output_named(gbuffer, "scene.depth");
  const std::vector<uint8_t> depth_raw = capture_->load(depth);
  std::vector<std::string> names;
  const std::vector<float> exr = read_image(dir / "all" / "scene.depth.exr", w, h, c, &names);
  ASSERT_EQ(c, 2);
  const size_t z = names[0] == "Z" ? 0 : 1;
  ASSERT_EQ(names[z], "Z");
  ASSERT_EQ(names[1 - z], "S");
  for (auto [x, y] : kPixels) {
    const uint64_t index = uint64_t(y) * 320 + x;
    EXPECT_EQ(exr[index * 2 + z], float_at(depth_raw, 4 * index));
    EXPECT_EQ(exr[index * 2 + 1 - z], float(depth_raw[320 * 180 * 4 + index]));
  }

  const ResourceRecord& pyramid = output_named(pass_named(frame0(), "depth.pyramid"), "depth.pyramid");
  const std::vector<uint8_t> pyramid_raw = capture_->load(pyramid);
  const std::vector<float> mip1 = read_image(dir / "pyramid.exr", w, h, c);
  ASSERT_EQ(w, int(std::max(1u, pyramid.extent.width / 2)));
  ASSERT_EQ(c, 2);
  const uint64_t mip0_bytes = uint64_t(pyramid.extent.width) * pyramid.extent.height * 8;
  for (uint64_t i = 0; i < uint64_t(w) * h; ++i) {
    ASSERT_EQ(mip1[2 * i], float_at(pyramid_raw, mip0_bytes + 8 * i)) << i;
    ASSERT_EQ(mip1[2 * i + 1], float_at(pyramid_raw, mip0_bytes + 8 * i + 4)) << i;
  }

  // Stencil as a palette: plain static geometry (0) is black.
  const std::vector<float> stencil = read_image(dir / "stencil.png", w, h, c);
  for (auto [x, y] : kPixels) {
    const uint32_t tag = depth_raw[320 * 180 * 4 + uint64_t(y) * 320 + x];
    if (tag == 0) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(stencil[(size_t(y) * w + x) * c + k], 0.0f);
    }
  }
  EXPECT_NE(run.result.err.find("expected a .exr file"), std::string::npos) << run.result.err;

  // HDR colour tonemapped: x / (1 + x), then the sRGB curve.
  const ResourceRecord& lit = output_named(pass_named(frame0(), "lighting.composite"), "lighting.lit");
  const std::vector<uint8_t> lit_raw = capture_->load(lit);
  const std::vector<float> lit_png = read_image(dir / "lit.png", w, h, c);
  for (auto [x, y] : kPixels)
    for (int k = 0; k < 3; ++k) {
      const double v = half_at(lit_raw, 8 * (uint64_t(y) * 320 + x) + 2 * k), t = v > 0 ? v / (1 + v) : 0;
      const double srgb = t <= 0.0031308 ? 12.92 * t : 1.055 * std::pow(t, 1 / 2.4) - 0.055;
      EXPECT_NEAR(lit_png[(size_t(y) * w + x) * c + k] * 255.0, srgb * 255.0, 0.51) << x << "," << y;
    }

  // Depth linearised: znear / depth on a log scale from the nearest (white) to the farthest
  // (black) drawn texel; nothing drawn is black.
  const std::vector<float> depth_png = read_image(dir / "all" / "scene.depth.png", w, h, c);
  const double znear = frame0().camera.znear;
  double nearest = INFINITY, farthest = 0;
  for (uint64_t i = 0; i < 320 * 180; ++i)
    if (const float d = float_at(depth_raw, 4 * i); d > 0) {
      nearest = std::min(nearest, znear / d);
      farthest = std::max(farthest, znear / d);
    }
  for (uint64_t i = 0; i < 320 * 180; ++i) {
    const float d = float_at(depth_raw, 4 * i);
    const double grey = d > 0 ? 1 - std::log(znear / d / nearest) / std::log(farthest / nearest) : 0;
    ASSERT_NEAR(depth_png[i * c] * 255.0, grey * 255.0, 0.51) << i;
  }

  // Motion on a colour wheel: no motion is black, the longest motion at full brightness.
  const ResourceRecord& motion = output_named(gbuffer, "gbuffer.motion");
  const std::vector<uint8_t> motion_raw = capture_->load(motion);
  const std::vector<float> motion_png = read_image(dir / "all" / "gbuffer.motion.png", w, h, c);
  double longest = 0;
  uint64_t longest_at = 0;
  for (uint64_t i = 0; i < 320 * 180; ++i) {
    const double length = std::hypot(half_at(motion_raw, 4 * i) * 320, half_at(motion_raw, 4 * i + 2) * 180);
    if (length > longest) longest = length, longest_at = i;
    if (length == 0) {
      for (int k = 0; k < 3; ++k) ASSERT_EQ(motion_png[i * c + k], 0.0f) << i;
    }
  }
  ASSERT_GT(longest, 0);
  EXPECT_EQ(std::max({motion_png[longest_at * c], motion_png[longest_at * c + 1], motion_png[longest_at * c + 2]}),
            1.0f);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
