// A folder of a unit test's own: unique to its process (CTest runs each test in a process of its
// own), emptied first and removed when the test ends.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace nightcap {

struct ScratchFolder {
  const std::filesystem::path path;
  explicit ScratchFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("nightcap-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

}  // namespace nightcap
