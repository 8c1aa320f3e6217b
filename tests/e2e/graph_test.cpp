// `nightcap graph --dot` end to end: every pass and resource version of the recorded frame is in
// the DOT, with the edges the manifest implies, and Graphviz renders it, hostile names included.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "tests/e2e/cli.h"
#include "tests/under_ci.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kCity = "--city-block --size 320x180 --frames 2";
const char* kWalk = "--city-block --size 160x90 --frames 8 --cut-at 5";  // as tests/e2e/history_test.cpp

struct Node {
  std::string attributes, label;  // label as written in the DOT, escapes included
};

struct Dot {
  std::map<std::string, Node> nodes;
  std::set<std::pair<std::string, std::string>> edges;
  std::vector<std::string> pass_ids;  // in the order written
};

// The graph as nightcap writes it: one statement a line, generated ids, quoted labels last.
Dot parse_dot(const std::string& text) {
  static const std::regex node(R"re(^  (\w+) \[(.*)label="((?:[^"\\]|\\.)*)"\];$)re");
  static const std::regex edge(R"re(^  (\w+) -> (\w+)( \[.*\])?;$)re");
  Dot dot;
  std::istringstream lines(text);
  std::string line;
  std::smatch m;
  while (std::getline(lines, line)) {
    if (std::regex_match(line, m, node)) {
      dot.nodes[m[1]] = {m[2], m[3]};
      if (m[1].str()[0] == 'p') dot.pass_ids.push_back(m[1]);
    } else if (std::regex_match(line, m, edge)) {
      dot.edges.insert({m[1], m[2]});
    }
  }
  return dot;
}

// A name as nightcap escapes it in a label: names hold no backslash or control character, so only
// `"` and `&` need it.
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '"' ? "\\\"" : c == '&' ? "&amp;" : std::string(1, c);
  return out;
}

// The resource's label as the DOT must show it: name, then format and size or buffer bytes.
std::string resource_label(const nlohmann::json& r) {
  std::string text = escaped(r.at("resource")) + "\\n";
  if (r.at("format") == "BUFFER") return text + std::to_string(r.at("bytes").get<uint64_t>()) + " bytes";
  text += r.at("format").get<std::string>() + " " + std::to_string(r.at("width").get<int>()) + "x" +
          std::to_string(r.at("height").get<int>());
  if (r.value("depth", 1) > 1) text += "x" + std::to_string(r.at("depth").get<int>());  // lights.clusters' slices
  if (r.at("mips") > 1) text += ", " + std::to_string(r.at("mips").get<int>()) + " mips";
  if (r.at("layers") > 1) text += ", " + std::to_string(r.at("layers").get<int>()) + " layers";
  return text;
}

// The first two lines of a resource node's label: name, then format and size.
std::string resource_text(const Dot& dot, const std::string& id) {
  const std::string& label = dot.nodes.at(id).label;
  const size_t first = label.find("\\n");
  return label.substr(0, first == std::string::npos ? first : label.find("\\n", first + 2));
}

// Every pass of `frame` is a node in execution order, with its status (and reason when skipped),
// and each of its inputs and outputs is an edge from or to a node labelled with that resource.
void expect_frame_drawn(const Dot& dot, const nlohmann::json& frame) {
  const auto& passes = frame.at("passes");
  ASSERT_EQ(dot.pass_ids.size(), passes.size());
  for (size_t i = 0; i < passes.size(); ++i) {
    const nlohmann::json& p = passes[i];
    const std::string name = p.at("name");
    const Node& node = dot.nodes.at(dot.pass_ids[i]);
    const std::string heading = std::to_string(i) + ". " + escaped(name) + "\\n";
    EXPECT_EQ(node.label.rfind(heading, 0), 0u) << name << ": " << node.label;
    if (p.at("status") == "ran") {
      EXPECT_NE(node.label.find("ran, "), std::string::npos) << name;
      EXPECT_NE(node.label.find(" ms (" + p.at("clock").get<std::string>() + ")"), std::string::npos) << name;
    } else {
      EXPECT_NE(node.label.find("skipped: "), std::string::npos) << name;
      EXPECT_NE(node.attributes.find("dashed"), std::string::npos) << name;
    }
    std::multiset<std::string> inputs, outputs, drawn_inputs, drawn_outputs;
    for (const auto& r : p.at("inputs")) inputs.insert(resource_label(r));
    for (const auto& r : p.at("outputs")) outputs.insert(resource_label(r));
    for (const auto& [from, to] : dot.edges) {
      if (to == dot.pass_ids[i]) drawn_inputs.insert(resource_text(dot, from));
      if (from == dot.pass_ids[i]) drawn_outputs.insert(resource_text(dot, to));
    }
    EXPECT_EQ(drawn_inputs, inputs) << name;
    EXPECT_EQ(drawn_outputs, outputs) << name;
  }
}

bool dot_installed() { return std::system("command -v dot >/dev/null 2>&1") == 0; }

// Graphviz's rendering of `dot_text` as SVG; the caller has required `dot` (dot_installed).
std::string render_svg(const std::string& dot_text, const fs::path& dir) {
  std::ofstream(dir / "graph.dot", std::ios::binary) << dot_text;
  const std::string command =
      "dot -Tsvg " + quote(dir / "graph.dot") + " -o " + quote(dir / "graph.svg") + " 2>" + quote(dir / "dot.err");
  const int status = std::system(command.c_str());
  std::ifstream err(dir / "dot.err"), svg(dir / "graph.svg");
  std::stringstream err_text, svg_text;
  err_text << err.rdbuf();
  svg_text << svg.rdbuf();
  EXPECT_EQ(status, 0) << err_text.str();
  EXPECT_TRUE(err_text.str().empty()) << err_text.str();
  EXPECT_NE(svg_text.str().find("<svg"), std::string::npos) << "no SVG produced";
  return svg_text.str();
}

TEST(Graph, DotDrawsEveryPassAndResourceVersion) {
  const fs::path capture = shared_capture("city", kCity);
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  for (int frame : {0, 1}) {
    const CliResult r = run_cli("graph --dot " + quote(capture) + (frame ? " --frame 1" : ""));
    ASSERT_EQ(r.code, 0) << r.err;
    const Dot dot = parse_dot(r.out);
    expect_frame_drawn(dot, manifest.at("frames")[frame]);
    // scene.depth is written by depth.prepass, then by gbuffer.opaque: one node per version.
    int depth_versions = 0;
    for (const auto& [id, node] : dot.nodes) depth_versions += node.label.rfind("scene.depth\\n", 0) == 0;
    EXPECT_EQ(depth_versions, 2) << "frame " << frame;
  }
  // -o writes what stdout shows.
  const fs::path dir = scratch("svg");
  const CliResult r = run_cli("graph --dot -o " + quote(dir / "frame0.dot") + " " + quote(capture));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  std::ifstream file(dir / "frame0.dot");
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_EQ(text.str(), run_cli("graph --dot " + quote(capture)).out);
  NIGHTCAP_REQUIRE_TOOL(dot_installed(), "Graphviz `dot`");
  render_svg(text.str(), dir);
}

TEST(Graph, HistoryEdgesComeFromThePreviousFrameAndGoToTheNext) {
  const fs::path capture = shared_capture("walk-8", kWalk);
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  std::vector<std::string> drawn;  // each frame's DOT, rendered once all frames are checked
  for (const auto& [frame, origin] : std::vector<std::pair<int, std::string>>{
           {0, "initial value (no earlier frame)"}, {3, "from frame 2"}, {5, "initial value (camera cut)"}}) {
    const CliResult r = run_cli("graph --dot --frame " + std::to_string(frame) + " " + quote(capture));
    ASSERT_EQ(r.code, 0) << r.err;
    const Dot dot = parse_dot(r.out);
    expect_frame_drawn(dot, manifest.at("frames")[frame]);
    std::string history_node;
    std::set<std::string> kept_nodes;  // one per resource kept for the next frame
    for (const auto& [id, node] : dot.nodes) {
      if (node.label.rfind("exposure.value@previous\\n", 0) == 0) history_node = id;
      if (node.label == "history of frame " + std::to_string(frame + 1)) kept_nodes.insert(id);
    }
    ASSERT_FALSE(history_node.empty()) << r.out;
    EXPECT_NE(dot.nodes.at(history_node).label.find(origin), std::string::npos) << dot.nodes.at(history_node).label;
    EXPECT_NE(dot.nodes.at(history_node).attributes.find("dashed"), std::string::npos);
    ASSERT_FALSE(kept_nodes.empty()) << "what this frame leaves for the next";
    bool kept_from_exposure = false;
    for (const auto& [from, to] : dot.edges)
      kept_from_exposure |= kept_nodes.count(to) && dot.nodes.at(from).label.rfind("exposure.value\\n", 0) == 0;
    EXPECT_TRUE(kept_from_exposure);
    drawn.push_back(r.out);
  }
  NIGHTCAP_REQUIRE_TOOL(dot_installed(), "Graphviz `dot`");
  for (size_t i = 0; i < drawn.size(); ++i) render_svg(drawn[i], scratch("svg-history-" + std::to_string(i)));
}

TEST(Graph, SkippedPassesAreDashedWithTheirReason) {
  const fs::path copy = scratch("capture") / "culled";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  nlohmann::json manifest = read_json(copy / "manifest.json");
  for (auto& p : manifest.at("frames")[0].at("passes"))
    if (p.at("name") == "normals.pack") {
      p["status"] = "skipped";
      p["reason"] = "culled: no pass consumes its outputs";
      p["gpu_ms"] = nullptr;
      p["outputs"] = nlohmann::json::array();
    }
  write_json(copy / "manifest.json", manifest);
  const CliResult r = run_cli("graph --dot " + quote(copy));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_frame_drawn(parse_dot(r.out), manifest.at("frames")[0]);
  EXPECT_NE(r.out.find("normals.pack\\nskipped: culled: no pass consumes its outputs"), std::string::npos) << r.out;
  NIGHTCAP_REQUIRE_TOOL(dot_installed(), "Graphviz `dot`");
  render_svg(r.out, scratch("svg"));
}

TEST(Graph, HostileNamesAreEscaped) {
  // The reader accepts any printable ASCII name without '/', '\' or spaces; a reason is free text.
  const std::string pass_name = "x\"y<script>alert(1)<b>{z}|&lt;";
  const std::string resource_name = "d\"<b>}{&amp;";
  const std::string reason = "a \"quoted\" \\back\\slash\nnew line <i>";
  const fs::path copy = scratch("capture") / "hostile";
  fs::copy(shared_capture("city", kCity), copy, fs::copy_options::recursive);
  nlohmann::json manifest = read_json(copy / "manifest.json");
  for (auto& p : manifest.at("frames")[0].at("passes")) {
    if (p.at("name") == "depth.convert") p["name"] = pass_name;
    if (p.at("name") == "tonemap") {
      p["status"] = "skipped";
      p["reason"] = reason;
    }
    for (const char* side : {"inputs", "outputs"})
      for (auto& res : p.at(side))
        if (res.at("resource") == "depth.linear") res["resource"] = resource_name;
  }
  write_json(copy / "manifest.json", manifest);
  const CliResult r = run_cli("graph --dot " + quote(copy));
  ASSERT_EQ(r.code, 0) << r.err;
  expect_frame_drawn(parse_dot(r.out), manifest.at("frames")[0]);
  EXPECT_NE(r.out.find(R"(x\"y<script>alert(1)<b>{z}|&amp;lt;)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(R"(label="d\"<b>}{&amp;amp;\n)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(R"(skipped: a \"quoted\" \\back\\slash\nnew line <i>")"), std::string::npos) << r.out;

  NIGHTCAP_REQUIRE_TOOL(dot_installed(), "Graphviz `dot`");
  const std::string svg = render_svg(r.out, scratch("svg"));
  // Graphviz shows the names as text, exactly as recorded, and nothing of them becomes markup.
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_EQ(svg.find("<b>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;script&gt;alert(1)&lt;b&gt;{z}|&amp;lt;"), std::string::npos) << svg;
  EXPECT_NE(svg.find("}{&amp;amp;"), std::string::npos) << svg;
  EXPECT_NE(svg.find("\\back\\slash<"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">new line &lt;i&gt;<"), std::string::npos) << svg;
}

TEST(Graph, BadFrameOrCaptureIsRefused) {
  const fs::path capture = shared_capture("city", kCity);
  CliResult r = run_cli("graph --dot --frame 2 " + quote(capture));
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("--frame 2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((capture / "manifest.json").string()), std::string::npos) << r.err;

  r = run_cli("graph --dot --frame -1 " + quote(capture));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--frame"), std::string::npos) << r.err;

  const fs::path dir = scratch("bad");
  r = run_cli("graph --dot " + quote(dir / "missing"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find((dir / "missing").string()), std::string::npos) << r.err;

  r = run_cli("graph --dot -o " + quote(dir / "no-such-folder" / "g.dot") + " " + quote(capture));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find((dir / "no-such-folder" / "g.dot").string()), std::string::npos) << r.err;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
