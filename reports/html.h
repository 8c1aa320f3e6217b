// Text that comes from a scene or a capture (names, reasons, parameters, GLSL) goes into the
// report's HTML and SVG only through these, so that none of it can become markup.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace nightcap {

// `text` with & < > " ' replaced by entities: safe as element content and as a quoted attribute
// value, in HTML and in SVG. Bytes that are not printable ASCII or valid UTF-8 become U+FFFD, so
// a hostile name cannot break the page's encoding either.
std::string escape_html(std::string_view text);

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

}  // namespace nightcap
