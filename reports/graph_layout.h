// The pass graph of a frame laid out by Graphviz's `dot` (the DOT of `nightcap graph`), as SVG.
#pragma once

#include <filesystem>
#include <string>

namespace nightcap {

// Writes `dot_text` to `dot_file` and lays it out with `dot -Tsvg` into `svg_file` (written
// beside its name and renamed into place). Throws std::runtime_error naming the file and what
// dot said when dot cannot be run or fails.
void layout_graph(const std::string& dot_text, const std::filesystem::path& dot_file,
                  const std::filesystem::path& svg_file);

}  // namespace nightcap
