// A text file's lines, for the tests that read the repository's own pages and scripts.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace nightcap {

inline std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace nightcap
