#include "reports/frame_graphs.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "compare/parallel.h"
#include "inspect/graph_dot.h"
#include "inspect/overview_dot.h"
#include "reports/graph_layout.h"

namespace nightcap {
namespace {

namespace fs = std::filesystem;

// The <svg> element of a file Graphviz wrote, without the XML prolog and doctype that may not
// appear inside an HTML page.
std::string inline_svg(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string svg = text.str();
  const size_t start = svg.find("<svg");
  if (!in || start == std::string::npos) throw std::runtime_error(file.string() + ": not an SVG picture");
  return svg.substr(start);
}

}  // namespace

FrameGraphs draw_frame_graphs(const FrameRecord& frame, const fs::path& folder,
                              const std::function<std::string(size_t)>& anchor) {
  const PassLink link = [&](size_t index) { return "#" + anchor(index); };
  FrameGraphs graphs;
  layout_graph(frame_to_dot(frame), folder / "graph.dot", folder / "graph.svg");
  layout_graph(frame_overview_dot(frame, link), folder / "overview.dot", folder / "overview.svg");
  graphs.overview = inline_svg(folder / "overview.svg");
  fs::create_directories(folder / "graphs");
  graphs.passes.resize(frame.passes.size());
  // Numbered files: a pass name never becomes part of a path.
  for_each_on_cores(frame.passes.size(), [&](size_t i) {
    const fs::path base = folder / "graphs" / ("pass-" + std::to_string(i));
    layout_graph(pass_to_dot(frame, i, link), base.string() + ".dot", base.string() + ".svg");
    graphs.passes[i] = inline_svg(base.string() + ".svg");
  });
  return graphs;
}

}  // namespace nightcap
