// Running the nightcap CLI from tests, and captures shared between test processes.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace nightcap::test {

struct CliResult {
  int code = -1;
  std::string out, err;
};

// Runs `nightcap ARGS` (a shell-quoted argument string) and collects its exit code and output.
// `environment`: shell-quoted NAME=VALUE assignments for that run only.
CliResult run_cli(const std::string& args, const std::string& environment = "");

// A scratch folder unique to this test, emptied first.
std::filesystem::path scratch(const std::string& name);

// A capture rendered once per build with `args` and shared by every test that asks for the
// same key; a file lock keeps concurrent test processes from rendering it twice. A render that
// exits non-zero fails the calling test.
std::filesystem::path shared_capture(const std::string& key, const std::string& args);

nlohmann::json read_json(const std::filesystem::path& file);
// A file's bytes as a string (empty when it cannot be read).
std::string slurp(const std::filesystem::path& file);
void write_json(const std::filesystem::path& file, const nlohmann::json& json);
std::string quote(const std::filesystem::path& path);

}  // namespace nightcap::test
