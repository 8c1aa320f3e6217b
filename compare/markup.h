// Text from a scene or a capture (names, reasons, parameters, GLSL, messages) made safe to put in
// markup: the HTML reports and SVG (reports/), and the JUnit XML of `diff` (diff_results.*).
#pragma once

#include <string>
#include <string_view>

namespace nightcap {

// `text` with & < > " ' replaced by entities: safe as element content and as a quoted attribute
// value, in HTML, SVG and XML. Control characters other than tab and line breaks, and bytes that
// are not valid UTF-8, become U+FFFD, so a hostile name cannot break the document's encoding or
// make XML ill-formed either.
std::string escape_markup(std::string_view text);

}  // namespace nightcap
