// A capture diff as results a CI system reads: one test case per frame, pass and output (and per
// pass or frame that only one capture ran), each passed, failed or skipped; as counts for the
// last line of `nightcap diff`, and as JUnit XML.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "compare/diff.h"

namespace nightcap {

struct DiffCase {
  std::string suite;  // "frame K"
  // "PASS/RESOURCE", "PASS" for a pass-level result, "frame inputs" for a frame whose own inputs
  // differ, or "frame K"
  std::string name;
  enum class Outcome { passed, failed, skipped } outcome = Outcome::passed;
  std::string message;  // what it was held to and what was measured, or why it failed or was skipped
};

std::vector<DiffCase> diff_cases(const CaptureDiff& diff);

struct DiffTally {
  uint64_t passed = 0, failed = 0, skipped = 0;
};
DiffTally tally(const std::vector<DiffCase>& cases);

// One <testsuite> per frame. Throws std::runtime_error naming `file` when it cannot be written.
void write_junit(const std::filesystem::path& file, const std::vector<DiffCase>& cases, double seconds);

}  // namespace nightcap
