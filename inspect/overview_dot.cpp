#include "inspect/overview_dot.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "inspect/dot_text.h"
#include "passes/core/history_name.h"

namespace nightcap {
namespace {

// Who wrote what each pass read, within the frame: a version is a resource's content hash, so
// an input is the output of the last pass before it that wrote those bytes to that resource.
struct DataFlow {
  // writer[pass][input]: the pass that wrote that input, if any pass of the frame did.
  std::vector<std::vector<std::optional<size_t>>> writer;
  // readers[pass][output]: the later passes that read that output.
  std::vector<std::vector<std::vector<size_t>>> readers;

  explicit DataFlow(const FrameRecord& frame) : writer(frame.passes.size()), readers(frame.passes.size()) {
    std::map<std::string, std::pair<size_t, size_t>> latest;  // resource -> (pass, output)
    for (size_t p = 0; p < frame.passes.size(); ++p) {
      const PassRecord& pass = frame.passes[p];
      readers[p].resize(pass.outputs.size());
      for (const ResourceRecord& in : pass.inputs) {
        std::optional<size_t> from;
        if (auto it = latest.find(in.resource); it != latest.end()) {
          const auto [w, k] = it->second;
          if (frame.passes[w].outputs[k].hash == in.hash) {
            from = w;
            std::vector<size_t>& list = readers[w][k];
            if (list.empty() || list.back() != p) list.push_back(p);
          }
        }
        writer[p].push_back(from);
      }
      for (size_t k = 0; k < pass.outputs.size(); ++k) latest[pass.outputs[k].resource] = {p, k};
    }
  }
};

std::string milliseconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g ms", value);
  return text;
}

std::string url(const PassLink& link, size_t index) {
  const std::string target = link(index);
  return target.empty() ? "" : ", URL=\"" + dot_escape(target) + "\", target=\"_top\"";
}

// "a, b (+3)": names enough to recognise, the rest counted.
std::string joined(const std::vector<std::string>& names, size_t shown) {
  std::string text;
  for (size_t i = 0; i < names.size() && i < shown; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > shown) text += " (+" + std::to_string(names.size() - shown) + ")";
  return text;
}

std::string pass_node(const FrameRecord& frame, size_t p, const PassLink& link, bool bold) {
  const PassRecord& pass = frame.passes[p];
  std::ostringstream node;
  node << "  p" << p
       << " [shape=box, label=" << dot_label({pass.name, pass.ran ? milliseconds(pass.time_ms) : "skipped"})
       << ", tooltip=" << dot_label({pass.ran ? pass.name : pass.name + ": " + pass.reason})
       << (pass.ran ? (bold ? ", style=\"bold\"" : "") : ", style=\"dashed\", color=\"grey55\", fontcolor=\"grey40\"")
       << url(link, p) << "];\n";
  return node.str();
}

}  // namespace

std::string frame_overview_dot(const FrameRecord& frame, const PassLink& link) {
  std::ostringstream dot;
  dot << "digraph overview {\n  rankdir=TB;\n  ranksep=0.35;\n  nodesep=0.15;\n  newrank=true;\n  "
         "fontname=\"Helvetica\";\n  node [shape=box, fontname=\"Helvetica\", "
         "fontsize=10];\n  edge [fontname=\"Helvetica\", fontsize=8, color=\"grey40\", fontcolor=\"grey30\"];\n";
  // Stages in the order their first pass runs; cluster ids are generated, the stage is a label.
  std::vector<std::string> stages;
  for (const PassRecord& p : frame.passes)
    if (!p.stage.empty() && std::find(stages.begin(), stages.end(), p.stage) == stages.end()) stages.push_back(p.stage);
  for (size_t s = 0; s < stages.size(); ++s) {
    dot << " subgraph cluster_" << s << " {\n  label=" << dot_label({stages[s]})
        << ";\n  style=\"rounded,filled\";\n  fillcolor=\"grey96\";\n  color=\"grey75\";\n";
    for (size_t p = 0; p < frame.passes.size(); ++p)
      if (frame.passes[p].stage == stages[s]) dot << pass_node(frame, p, link, false);
    dot << " }\n";
  }
  for (size_t p = 0; p < frame.passes.size(); ++p)
    if (frame.passes[p].stage.empty()) dot << pass_node(frame, p, link, false);
  // One edge per pair of passes, however many resources flow between them.
  const DataFlow flow(frame);
  std::map<std::pair<size_t, size_t>, std::vector<std::string>> edges;
  for (size_t p = 0; p < frame.passes.size(); ++p)
    for (size_t k = 0; k < frame.passes[p].inputs.size(); ++k)
      if (const auto from = flow.writer[p][k]) {
        std::vector<std::string>& names = edges[{*from, p}];
        const std::string& resource = frame.passes[p].inputs[k].resource;
        if (std::find(names.begin(), names.end(), resource) == names.end()) names.push_back(resource);
      }
  for (const auto& [pair, names] : edges)
    dot << "  p" << pair.first << " -> p" << pair.second << " [tooltip=" << dot_label({joined(names, names.size())})
        << (frame.passes[pair.first].ran ? "" : ", style=\"dashed\", color=\"grey55\"") << "];\n";
  dot << "}\n";
  return dot.str();
}

std::string pass_to_dot(const FrameRecord& frame, size_t index, const PassLink& link) {
  const PassRecord& pass = frame.passes.at(index);
  const DataFlow flow(frame);
  std::ostringstream dot;
  dot << "digraph pass {\n  rankdir=LR;\n  node [fontname=\"Helvetica\", fontsize=9];\n  edge [color=\"grey40\"];\n"
      << pass_node(frame, index, link, true);
  for (size_t k = 0; k < pass.inputs.size(); ++k) {
    const ResourceRecord& in = pass.inputs[k];
    const std::optional<size_t> from = flow.writer[index][k];
    const bool history = !history_source(in.resource).empty();
    const std::string origin = from      ? "from " + frame.passes[*from].name
                               : history ? "the previous frame's"
                                         : "imported (scene, camera)";
    dot << "  i" << k << " [shape=ellipse, label=" << dot_label({in.resource, origin})
        << (history ? ", style=\"dashed\", color=\"blue\"" : "") << (from ? url(link, *from) : "") << "];\n"
        << "  i" << k << " -> p" << index << ";\n";
  }
  for (size_t k = 0; k < pass.outputs.size(); ++k) {
    const std::vector<size_t>& readers = flow.readers[index][k];
    std::vector<std::string> names;
    for (size_t r : readers) names.push_back(frame.passes[r].name);
    dot << "  o" << k << " [shape=ellipse, label="
        << dot_label(
               {pass.outputs[k].resource, names.empty() ? "read by no pass of the frame" : "to " + joined(names, 2)})
        << (readers.empty() ? "" : url(link, readers.front())) << "];\n"
        << "  p" << index << " -> o" << k << ";\n";
  }
  dot << "}\n";
  return dot.str();
}

}  // namespace nightcap
