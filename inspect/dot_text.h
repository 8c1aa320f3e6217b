// Text from a capture made safe for a double-quoted Graphviz DOT string.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nightcap {

// Text for a double-quoted DOT label. Graphviz reads it twice: the DOT lexer, where only \" is
// special, then the label itself, where a backslash starts an escape (\n, \l, \N, ...) and HTML
// entities such as &lt; are replaced. Nodes are plain boxes and ellipses, never records, so
// braces, '|' and '<>' need nothing; nor does the SVG renderer, which escapes its own output.
std::string dot_escape(std::string_view text);

// A quoted label of several lines, each escaped.
std::string dot_label(const std::vector<std::string>& lines);

}  // namespace nightcap
