// Under RenderDoc, `render` makes exactly one frame capture whose labelled regions are the
// GPU passes that ran, in order. tests/install-deps.sh installs RenderDoc, so under CI (CI=true)
// a missing tool fails the test; elsewhere it is skipped with a message.
//
// Sanitizer builds skip it. renderdoccmd preloads RenderDoc's library ahead of the
// AddressSanitizer runtime, which then refuses to start ("ASan runtime does not come first");
// with that check off (ASAN_OPTIONS=verify_asan_link_order=0) the render runs, but renderdoccmd
// mostly fails to connect to the slow-starting instrumented process ("Couldn't connect to target
// program", exit 4) and RenderDoc's library leaks 48 KB at exit.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace fs = std::filesystem;

bool under_ci() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

// Fails under CI, where the install script provides the tool; skips elsewhere.
#define REQUIRE_TOOL(available, what)                                                          \
  if (!(available)) {                                                                          \
    if (under_ci()) FAIL() << what << " is not installed (tests/install-deps.sh installs it)"; \
    GTEST_SKIP() << what << " is not installed";                                               \
  }

TEST(RenderDoc, OneCaptureLabelledWithThePassesThatRan) {
#ifdef NIGHTCAP_SANITIZE_BUILD
  GTEST_SKIP() << "RenderDoc cannot inject into a sanitizer build (see the comment above)";
#endif
  REQUIRE_TOOL(std::system("command -v renderdoccmd >/dev/null 2>&1") == 0, "renderdoccmd");
  const fs::path dir = scratch("rdc");
  const std::string command = "renderdoccmd capture -w -c " + quote(dir / "frame") + " " + NIGHTCAP_CLI +
                              " render --size 96x54 --frames 2 -o " + quote(dir / "capture") + " >" +
                              quote(dir / "log") + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << "renderdoccmd failed, see " << dir / "log";
  // renderdoccmd's exit code is its own: the render's success shows in its output.
  std::ifstream log(dir / "log");
  const std::string output((std::istreambuf_iterator<char>(log)), {});
  ASSERT_NE(output.find("capture written to"), std::string::npos) << output;
  std::vector<fs::path> captures;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".rdc") captures.push_back(e.path());
  ASSERT_EQ(captures.size(), 1u);

  // The passes that ran on the GPU, in order, from the capture's own manifest.
  std::vector<std::string> expected;
  const nlohmann::json manifest = read_json(dir / "capture" / "manifest.json");
  for (const auto& frame : manifest.at("frames"))
    for (const auto& p : frame.at("passes"))
      if (p.at("status") == "ran" && !p.at("gpu_ms").is_null()) expected.push_back(p.at("name"));

  REQUIRE_TOOL(std::system("/usr/bin/python3 -c 'import renderdoc' >/dev/null 2>&1") == 0, "python3-renderdoc");
  const std::string markers = "/usr/bin/python3 " + std::string(NIGHTCAP_SOURCE) + "/tests/e2e/renderdoc_markers.py " +
                              quote(captures[0]) + " >" + quote(dir / "markers") + " 2>" + quote(dir / "markers.err");
  ASSERT_EQ(std::system(markers.c_str()), 0) << "see " << dir / "markers.err";
  std::ifstream in(dir / "markers");
  std::vector<std::string> labels;
  for (std::string line; std::getline(in, line);) labels.push_back(line);
  EXPECT_EQ(labels, expected);
}

}  // namespace
}  // namespace nightcap::test
