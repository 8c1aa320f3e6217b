// A cube's flag is part of its resource record: it survives the manifest (replay must allocate
// and view the image as a cube), is absent for everything else, and a record that calls an
// image a cube without square faces and a multiple of 6 layers is refused.
#include <gtest/gtest.h>

#include "captures/capture.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

CaptureManifest manifest_with(const ResourceRecord& output) {
  CaptureManifest manifest;
  manifest.device = manifest.settings = manifest.scene = nlohmann::json::object();
  FrameRecord frame;
  frame.width = 32;
  frame.height = 32;
  PassRecord pass;
  pass.name = "probe.render";
  pass.ran = true;
  pass.outputs.push_back(output);
  frame.passes.push_back(pass);
  manifest.frames.push_back(frame);
  return manifest;
}

ResourceRecord cube_record() {
  ResourceRecord r;
  r.resource = "probe.cube";
  r.kind = kinds::hdr_colour;
  r.is_buffer = false;
  r.format = VK_FORMAT_R16G16B16A16_SFLOAT;
  r.extent.width = r.extent.height = 16;
  r.extent.layers = 6;
  r.cube = true;
  r.hash = std::string(32, 'a');
  r.blob = "blobs/" + r.hash + ".exr";
  return r;
}

TEST(ManifestCube, TheFlagRoundTripsAndIsAbsentForOtherImages) {
  nlohmann::json json = to_json(manifest_with(cube_record()));
  const CaptureManifest read = manifest_from_json(json, "manifest.json");
  EXPECT_TRUE(read.frames.at(0).passes.at(0).outputs.at(0).cube);

  ResourceRecord array = cube_record();
  array.cube = false;
  EXPECT_FALSE(to_json(array).contains("cube"));
  EXPECT_FALSE(manifest_from_json(to_json(manifest_with(array)), "manifest.json").frames[0].passes[0].outputs[0].cube);
}

TEST(ManifestCube, ACubeThatCannotBeOneIsRefused) {
  ResourceRecord four = cube_record();
  four.extent.layers = 4;
  try {
    manifest_from_json(to_json(manifest_with(four)), "manifest.json");
    ADD_FAILURE() << "a 4-layer cube was accepted";
  } catch (const CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find("a cube needs square faces and a multiple of 6 layers"), std::string::npos)
        << e.what();
  }
  nlohmann::json json = to_json(manifest_with(cube_record()));
  json["frames"][0]["passes"][0]["outputs"][0]["cube"] = "yes";
  EXPECT_THROW(manifest_from_json(json, "manifest.json"), CaptureError);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
