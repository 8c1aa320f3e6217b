// The readers under test take files, as the tools do: a harness writes each input to a file of
// its own process's scratch folder (in /dev/shm when there is one, so no disk is touched), which
// is removed when the process exits.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

namespace nightcap::fuzz {

inline const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path shm = "/dev/shm";
    const std::filesystem::path base =
        std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
    std::filesystem::path made = base / ("nightcap-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(made);
    std::atexit([] { std::filesystem::remove_all(scratch_folder()); });
    return made;
  }();
  return folder;
}

inline std::filesystem::path write_scratch(const std::string& name, std::span<const uint8_t> bytes) {
  const std::filesystem::path file = scratch_folder() / name;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out.flush()) std::abort();  // a harness that cannot write its input tests nothing
  return file;
}

}  // namespace nightcap::fuzz
