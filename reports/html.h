// What the report pages share. Text that comes from a scene or a capture goes into them only
// through escape_markup (compare/markup.h), so that none of it can become markup.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "compare/markup.h"

namespace nightcap {

// A number as the report prints it: up to `digits` significant digits, no exponent for ordinary
// magnitudes, "∞"/"NaN" spelled out.
std::string format_number(double value, int digits = 4);

// The start of a report page up to and including <body>: UTF-8, the generator mark that
// `report --force` looks for (kReportGenerator), the title (escaped here), report.css and, where
// asked, report.js.
inline constexpr std::string_view kReportGenerator = "<meta name=\"generator\" content=\"nightcap report\">";
std::string page_start(std::string_view title, bool with_script);

// Writes `text` to `file`; throws std::runtime_error naming the file when it cannot.
void write_file(const std::filesystem::path& file, std::string_view text);

// Creates `folder` for a report: it must not exist or be empty (std::runtime_error otherwise).
void start_report_folder(const std::filesystem::path& folder);
// Writes the page as `folder`/index.html, beside its name and renamed into place, last of the
// report's files: a report cut short has no index.html.
void publish_page(const std::filesystem::path& folder, std::string_view html);

}  // namespace nightcap
