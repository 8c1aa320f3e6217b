// Loading a static HTML page in headless Chromium and reporting what tests assert on: console
// errors, the layout of the passes' sections and the images, without pixel goldens.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/under_ci.h"

namespace nightcap::test {

// Debian 12's package `chromium` (tests/install-deps.sh).
inline const std::filesystem::path kChromium = "/usr/bin/chromium";

struct PageImage {
  std::string src;  // the attribute as written in the page, not the resolved URL
  int natural_width = 0, natural_height = 0;
  bool complete = false;
};
struct PageSection {
  std::string pass;  // data-pass
  double width = 0, height = 0;
};
struct PageCheck {
  // What DevTools shows as errors: console.error and console.assert, uncaught exceptions and
  // rejections, failed resource loads (each with the URL that failed).
  std::vector<std::string> console_errors;
  std::vector<PageSection> sections;  // section.pass in document order
  std::vector<PageImage> images;      // every <img> in document order
  std::string title;
  nlohmann::json script_result;  // what check_page's `script` gave
};

// Loads `html` (a file) in headless Chromium and returns what it saw once `load` has fired and
// its handlers have run, and, where `script` is given, once that JavaScript expression (a
// promise is awaited) has run in the page as a user's actions would: its value is in
// script_result, and what it made the page log is among the console errors. Throws
// std::runtime_error (with chromium's stderr) when Chromium cannot be run, the page cannot be
// loaded, or it never reported within 60 s. `scratch` holds the browser's profile.
PageCheck check_page(const std::filesystem::path& html, const std::filesystem::path& scratch,
                     const std::string& script = "");

// Writes a screenshot of `html` at the given viewport size to `png`.
void screenshot_page(const std::filesystem::path& html, const std::filesystem::path& png, int width, int height,
                     const std::filesystem::path& scratch);

// Chromium is installed by tests/install-deps.sh: see tests/under_ci.h.
#define NIGHTCAP_REQUIRE_CHROMIUM() \
  NIGHTCAP_REQUIRE_TOOL(std::filesystem::exists(::nightcap::test::kChromium), ::nightcap::test::kChromium.string())

}  // namespace nightcap::test
