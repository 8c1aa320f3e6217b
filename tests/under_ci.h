// Whether the tests run under CI, decided one way for every test. `.ci/run` exports CI=true; any
// value but empty, "0" or "false" counts, as CI services set it. Under CI a tool that
// tests/install-deps.sh installs must be there, so its absence fails the test; elsewhere the test
// is skipped, and tests/run-tests.sh (the README's test command) still fails on the skip.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string_view>

namespace nightcap::test {

inline bool under_ci() {
  const char* ci = std::getenv("CI");
  if (!ci) return false;
  const std::string_view value(ci);
  return !value.empty() && value != "0" && value != "false";
}

}  // namespace nightcap::test

// Fails under CI, skips elsewhere, when `available` is false; `what` names the missing tool.
#define NIGHTCAP_REQUIRE_TOOL(available, what)                                                                   \
  if (!(available)) {                                                                                            \
    if (::nightcap::test::under_ci()) FAIL() << what << " is not installed (tests/install-deps.sh installs it)"; \
    GTEST_SKIP() << what << " is not installed";                                                                 \
  }
