// Text that comes from a scene or a capture (names, reasons, parameters, GLSL) goes into the
// report's HTML and SVG only through these, so that none of it can become markup.
#pragma once

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

}  // namespace nightcap
