// The report's static files, embedded into the program at build time (embed_assets.cmake) so a
// report can be written wherever the CLI runs.
#pragma once

#include <string_view>

namespace nightcap {

std::string_view report_stylesheet();  // reports/report.css
std::string_view report_script();      // reports/report.js

}  // namespace nightcap
