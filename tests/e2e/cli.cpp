#include "tests/e2e/cli.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

namespace nightcap::test {
namespace fs = std::filesystem;

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

namespace {

fs::path test_root() {
  fs::path root = fs::temp_directory_path() / ("nightcap-e2e-" + std::to_string(getuid()));
  fs::create_directories(root);
  return root;
}

}  // namespace

std::string quote(const fs::path& path) { return "'" + path.string() + "'"; }

CliResult run_cli(const std::string& args, const std::string& environment) {
  const fs::path dir = test_root() / ("run-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string command = (environment.empty() ? "" : "env " + environment + " ") + std::string(NIGHTCAP_CLI) +
                              " " + args + " >" + quote(dir / "out") + " 2>" + quote(dir / "err") + " </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = slurp(dir / "out");
  result.err = slurp(dir / "err");
  return result;
}

fs::path scratch(const std::string& name) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = test_root() / (std::string(info->test_suite_name()) + "." + info->name()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path shared_capture(const std::string& key, const std::string& args) {
  const fs::path dir = fs::path(NIGHTCAP_CLI).parent_path() / "test-captures";
  fs::create_directories(dir);
  // Keyed by the CLI's build time: a rebuilt renderer never reuses an older build's capture.
  const auto built = fs::last_write_time(NIGHTCAP_CLI).time_since_epoch().count();
  const fs::path capture = dir / (key + "-" + std::to_string(built));
  // Captures of earlier builds are never read again.
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(key + "-", 0) == 0 && name != capture.filename().string() &&
        name.substr(key.size() + 1).find_first_not_of("-0123456789") == std::string::npos)
      fs::remove_all(entry.path(), error);
  }
  // One test process renders it while the others wait on the lock: every render that runs must
  // succeed, so a validation error (exit 2) in a shared capture fails the test that made it.
  const fs::path lock_file = dir / (key + ".lock");
  const int lock = ::open(lock_file.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock < 0 || ::flock(lock, LOCK_EX) != 0) ADD_FAILURE() << lock_file << ": cannot lock";
  if (!fs::exists(capture / "manifest.json")) {
    const CliResult r = run_cli("render " + args + " -o " + quote(capture));
    if (r.code != 0) ADD_FAILURE() << "render " << args << " failed (" << r.code << "): " << r.err;
  }
  if (lock >= 0) ::close(lock);
  return capture;
}

nlohmann::json read_json(const fs::path& file) { return nlohmann::json::parse(slurp(file)); }

void write_json(const fs::path& file, const nlohmann::json& json) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << json.dump(1);
}

}  // namespace nightcap::test
