// Commands that decode no image start without OpenImageIO: the dynamic loader never maps it nor
// the image module. A command that needs the module and cannot load it says which file and why.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kSmall = "--city-block --size 64x36";

TEST(ImageModule, CommandsThatDecodeNoImageNeverLoadIt) {
  const fs::path capture = shared_capture("city-small", kSmall);
  for (const std::string& command :
       {std::string("--help"), "passes " + quote(capture), "passes --json " + quote(capture),
        "graph --dot " + quote(capture), "diff " + quote(capture) + " " + quote(capture)}) {
    // LD_DEBUG=files: the dynamic loader lists on stderr every object it maps.
    const CliResult r = run_cli(command, "LD_DEBUG=files");
    EXPECT_EQ(r.code, 0) << command << ": " << r.err;
    EXPECT_NE(r.err.find("libvulkan"), std::string::npos) << command << ": the loader listed nothing";
    EXPECT_EQ(r.err.find("OpenImageIO"), std::string::npos) << command;
    EXPECT_EQ(r.err.find("nightcap_images"), std::string::npos) << command;
  }
}

TEST(ImageModule, AModuleThatCannotBeLoadedIsNamed) {
  const fs::path dir = scratch("out");
  const std::string box = quote(fs::path(NIGHTCAP_SHARED_DATA) / "gltf/BoxTextured/glTF/BoxTextured.gltf");
  const fs::path missing = dir / "missing" / "nightcap_images.so";
  CliResult r =
      run_cli("render " + box + " --size 64x36 -o " + quote(dir / "cap"), "NIGHTCAP_IMAGES_MODULE=" + quote(missing));
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("CesiumLogoFlat.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot find the image module " + missing.string() + " (named by NIGHTCAP_IMAGES_MODULE)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "cap"));

  const fs::path broken = dir / "broken.so";
  std::ofstream(broken) << "not a shared object";
  r = run_cli("render " + box + " --size 64x36 -o " + quote(dir / "cap"), "NIGHTCAP_IMAGES_MODULE=" + quote(broken));
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  // dlerror's reason follows the path.
  EXPECT_NE(r.err.find("cannot load the image module " + broken.string() + ": "), std::string::npos) << r.err;

  // Listing a capture needs no module.
  r = run_cli("passes " + quote(shared_capture("city-small", kSmall)), "NIGHTCAP_IMAGES_MODULE=" + quote(missing));
  EXPECT_EQ(r.code, 0) << r.err;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
