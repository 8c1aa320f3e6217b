// The README's test command is what .ci/run runs, and it fails on a skipped test or on none:
// tests/run-tests.sh is run on small CTest projects made here, one test passing, one skipped the
// way gtest_discover_tests marks a GoogleTest skip, and none.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "tests/unit/scratch_folder.h"
#include "tests/unit/text_lines.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

// The commands of the README's first fenced block, comments left out.
std::vector<std::string> readme_commands() {
  std::vector<std::string> commands;
  bool inside = false;
  for (const std::string& line : lines_of(fs::path(NIGHTCAP_SOURCE) / "README.md")) {
    if (line.rfind("```", 0) == 0) {
      if (inside) break;
      inside = true;
    } else if (inside && !line.empty() && line[0] != '#') {
      commands.push_back(line);
    }
  }
  return commands;
}

TEST(CiCommand, CiRunsTheReadmesTestCommandUnderCi) {
  const std::vector<std::string> commands = readme_commands();
  ASSERT_EQ(commands.size(), 2u) << "the README's first block holds the two commands";
  const std::vector<std::string> ci_lines = lines_of(fs::path(NIGHTCAP_SOURCE) / ".ci/run");
  ASSERT_FALSE(ci_lines.empty());
  EXPECT_EQ(ci_lines.back(), commands[1]);
  EXPECT_NE(std::find(ci_lines.begin(), ci_lines.end(), "export CI=true"), ci_lines.end());
  EXPECT_NE(commands[1].find("bash tests/run-tests.sh build"), std::string::npos);
}

// Exit status of tests/run-tests.sh on a CTest project whose tests are `tests` (CMake lines).
int run_tests_on(const std::string& name, const std::string& tests) {
  const ScratchFolder scratch("ci-command-" + name);
  std::ofstream(scratch.path / "CMakeLists.txt") << "cmake_minimum_required(VERSION 3.25)\nproject(probe NONE)\n"
                                                    "enable_testing()\n"
                                                 << tests;
  const std::string build = (scratch.path / "build").string();
  const std::string configure = "cmake -S '" + scratch.path.string() + "' -B '" + build + "' >/dev/null 2>&1";
  EXPECT_EQ(std::system(configure.c_str()), 0);
  const std::string run = "bash '" + std::string(NIGHTCAP_SOURCE) + "/tests/run-tests.sh' '" + build + "' >'" +
                          (scratch.path / "log").string() + "' 2>&1";
  const int status = std::system(run.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const char* kPassing = "add_test(NAME passes COMMAND sh -c \"exit 0\")\n";
const char* kSkipped =
    "add_test(NAME skipped COMMAND sh -c \"echo '[  SKIPPED ] not here'\")\n"
    "set_tests_properties(skipped PROPERTIES SKIP_REGULAR_EXPRESSION \"\\\\[  SKIPPED \\\\]\")\n";
const char* kFailing = "add_test(NAME fails COMMAND sh -c \"exit 1\")\n";

TEST(CiCommand, PassesOnlyWhenEveryTestRanAndPassed) {
  EXPECT_EQ(run_tests_on("pass", kPassing), 0);
  EXPECT_NE(run_tests_on("skip", std::string(kPassing) + kSkipped), 0) << "a skipped test fails the run";
  EXPECT_NE(run_tests_on("fail", std::string(kPassing) + kFailing), 0);
  EXPECT_NE(run_tests_on("none", ""), 0) << "no test at all fails the run";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
