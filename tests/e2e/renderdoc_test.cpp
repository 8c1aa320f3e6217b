// Under RenderDoc, `render` makes exactly one frame capture whose labelled regions are the
// GPU passes that ran, in order, and whose resource list names every image those passes used by
// its resource name (vkSetDebugUtilsObjectNameEXT). One capture serves both checks: it is the
// slow part. tests/install-deps.sh installs RenderDoc, so under CI (CI=true)
// a missing tool fails the test; elsewhere it is skipped with a message.
//
// Sanitizer builds skip it. renderdoccmd preloads RenderDoc's library ahead of the
// AddressSanitizer runtime, which then refuses to start ("ASan runtime does not come first");
// with that check off (ASAN_OPTIONS=verify_asan_link_order=0) the render runs, but renderdoccmd
// mostly fails to connect to the slow-starting instrumented process ("Couldn't connect to target
// program", exit 4) and RenderDoc's library leaks 48 KB at exit.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "tests/e2e/cli.h"
#include "tests/under_ci.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

// renderdoc_markers.py's output for the capture, one line per item; `mode` is empty or "--resources ".
std::vector<std::string> inspect_capture(const fs::path& capture, const std::string& mode, const fs::path& out) {
  const std::string command = "/usr/bin/python3 " + std::string(NIGHTCAP_SOURCE) + "/tests/e2e/renderdoc_markers.py " +
                              mode + quote(capture) + " >" + quote(out) + " 2>" + quote(out.string() + ".err");
  EXPECT_EQ(std::system(command.c_str()), 0) << "see " << out << ".err";
  std::ifstream in(out);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(RenderDoc, OneCaptureLabelledWithThePassesThatRanAndTheirImagesNamed) {
#ifdef NIGHTCAP_SANITIZE_BUILD
  GTEST_SKIP() << "RenderDoc cannot inject into a sanitizer build (see the comment above)";
#endif
  NIGHTCAP_REQUIRE_TOOL(std::system("command -v renderdoccmd >/dev/null 2>&1") == 0, "renderdoccmd");
  const fs::path dir = scratch("rdc");
  const std::string command = "renderdoccmd capture -w -c " + quote(dir / "frame") + " " + NIGHTCAP_CLI +
                              " render --city-block --size 96x54 --frames 2 -o " + quote(dir / "capture") + " >" +
                              quote(dir / "log") + " 2>&1";
  // renderdoccmd's exit code is its own, and not the render's: on a loaded machine the render
  // can finish before renderdoccmd connects to it to wait, and it then fails although the
  // .rdc was written. The render's success shows in its output and the .rdc file.
  const int code = std::system(command.c_str());
  std::ifstream log(dir / "log");
  const std::string output((std::istreambuf_iterator<char>(log)), {});
  ASSERT_NE(output.find("capture written to"), std::string::npos) << "renderdoccmd exit " << code << ": " << output;
  std::vector<fs::path> captures;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".rdc") captures.push_back(e.path());
  ASSERT_EQ(captures.size(), 1u) << "renderdoccmd exit " << code << ": " << output;

  // The passes that ran on the GPU, in order, and the images they read or wrote, from the
  // capture's own manifest.
  std::vector<std::string> expected;
  std::set<std::string> images;
  const nlohmann::json manifest = read_json(dir / "capture" / "manifest.json");
  for (const auto& frame : manifest.at("frames"))
    for (const auto& p : frame.at("passes")) {
      if (p.at("status") != "ran" || p.at("gpu_ms").is_null()) continue;
      expected.push_back(p.at("name"));
      for (const char* side : {"inputs", "outputs"})
        for (const auto& r : p.at(side))
          if (r.at("format") != "BUFFER") images.insert(r.at("resource").get<std::string>());
    }
  for (const char* image : {"gbuffer.normal", "scene.depth", "lighting.lit", "final.ldr"})
    ASSERT_TRUE(images.count(image)) << image << " is not among the manifest's images: the check below would miss it";

  NIGHTCAP_REQUIRE_TOOL(std::system("/usr/bin/python3 -c 'import renderdoc' >/dev/null 2>&1") == 0,
                        "python3-renderdoc");
  EXPECT_EQ(inspect_capture(captures[0], "", dir / "markers"), expected);

  std::set<std::string> named_textures;
  for (const std::string& line : inspect_capture(captures[0], "--resources ", dir / "resources"))
    if (line.rfind("Texture\t", 0) == 0) named_textures.insert(line.substr(std::string("Texture\t").size()));
  for (const std::string& image : images)
    EXPECT_TRUE(named_textures.count(image))
        << image << " has no texture of that name in RenderDoc's resource list, see " << dir / "resources";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
