// Scripted `nightcap inspect` runs for the e2e tests, with each command's --json line parsed, and
// the checks of a whole capture the stress tests share.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "captures/capture.h"
#include "compare/decoded_image.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {

// The small city the inspect tests share (as tests/e2e/capture_loop_test.cpp renders it).
inline constexpr const char* kCity = "--city-block --size 320x180 --frames 2";
// The same with froxels of 16 px and 32 slices (lights.cluster's tile_size and slices).
inline constexpr const char* kCityOtherFroxels =
    "--city-block --size 320x180 --frames 2 --set lights.cluster.tile_size=16 --set lights.cluster.slices=32";

struct Inspected {
  CliResult result;
  std::vector<nlohmann::json> objects;  // one per command that printed
};

// Runs `inspect CAPTURE -c COMMANDS` and parses each line of its output as one JSON object.
inline Inspected inspect(const std::filesystem::path& capture, const std::string& commands,
                         const std::string& environment = "") {
  Inspected run{run_cli("inspect " + quote(capture) + " -c '" + commands + "'", environment), {}};
  std::istringstream lines(run.result.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    run.objects.push_back(nlohmann::json::parse(line));
  }
  return run;
}

// A capture of frames 0 and 1: `inspect nan` searched both and found no NaN or Inf.
inline void expect_no_nan_or_inf(const std::filesystem::path& capture) {
  const Inspected nan = inspect(capture, "nan --json");
  ASSERT_EQ(nan.result.code, 0) << nan.result.err;
  EXPECT_EQ(nan.objects.at(0).at("frames"), nlohmann::json::array({0, 1})) << "every recorded frame searched";
  EXPECT_EQ(nan.objects.at(0).at("origins"), nlohmann::json::array()) << nan.objects.at(0).dump();
}

// A capture of frames 0 and 1: `replay --verify` of each exits 0 (every pass that ran reproduces
// what it recorded, bit for bit).
inline void expect_replays_verify(const std::filesystem::path& capture) {
  for (int frame : {0, 1}) {
    const CliResult replay = run_cli("replay --verify --frame " + std::to_string(frame) + " " + quote(capture));
    EXPECT_EQ(replay.code, 0) << "frame " << frame << ": " << replay.out << replay.err;
  }
}

// Tests of the shared city capture, opened for each test.
class CityCaptureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = shared_capture("city", kCity);
    capture_ = std::make_unique<Capture>(Capture::open(path_));
  }
  const FrameRecord& frame0() const { return capture_->frame(0); }

  std::filesystem::path path_;
  std::unique_ptr<Capture> capture_;
};

inline const PassRecord& pass_named(const FrameRecord& frame, const std::string& name) {
  for (const PassRecord& p : frame.passes)
    if (p.name == name) return p;
  throw std::runtime_error("no pass " + name);
}

inline const ResourceRecord& input_named(const PassRecord& pass, const std::string& name) {
  for (const ResourceRecord& r : pass.inputs)
    if (r.resource == name) return r;
  throw std::runtime_error(pass.name + " has no input " + name);
}

inline const ResourceRecord& output_named(const PassRecord& pass, const std::string& name) {
  for (const ResourceRecord& r : pass.outputs)
    if (r.resource == name) return r;
  throw std::runtime_error(pass.name + " has no output " + name);
}

// The decoded values of mip 0, layer 0 of image `resource` as `pass` of `frame` wrote it: the
// format's channels a texel (DecodedImage::subresource).
inline std::vector<float> decoded_output(const Capture& capture, const FrameRecord& frame, const std::string& pass,
                                         const std::string& resource) {
  const ResourceRecord& o = output_named(pass_named(frame, pass), resource);
  const std::vector<uint8_t> raw = capture.load(o);
  const DecodedImage decoded(o, raw);
  const std::span<const float> values = decoded.subresource(0, 0, 0);
  return {values.begin(), values.end()};
}

}  // namespace nightcap::test
