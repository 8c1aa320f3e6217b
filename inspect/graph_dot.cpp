#include "inspect/graph_dot.h"

#include <cstdio>
#include <map>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "inspect/dot_text.h"
#include "passes/core/history_name.h"

namespace nightcap {
namespace {

std::string milliseconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f ms", value);
  return text;
}

std::string shape_text(const ResourceRecord& r) {
  if (r.is_buffer) return std::to_string(r.buffer_size) + " bytes";
  const ImageExtent& e = r.extent;
  std::string text =
      std::string(format_info(r.format)->name) + " " + std::to_string(e.width) + "x" + std::to_string(e.height);
  if (e.depth > 1) text += "x" + std::to_string(e.depth);
  if (e.mips > 1) text += ", " + std::to_string(e.mips) + " mips";
  if (e.layers > 1) text += ", " + std::to_string(e.layers) + " layers";
  return text;
}

// Node ids are generated (p<pass>, r<version>), never taken from the capture, so only labels
// carry recorded text.
class FrameGraph {
 public:
  explicit FrameGraph(const FrameRecord& frame) : frame_(frame) {
    out_ << "digraph frame_" << frame.index << " {\n"
         << "  label=" << dot_label({"frame " + std::to_string(frame.index)}) << ";\n  labelloc=t;\n"
         << "  node [fontname=\"Helvetica\", fontsize=10];\n  edge [color=\"grey30\"];\n";
    for (size_t i = 0; i < frame.passes.size(); ++i) add_pass(i, frame.passes[i]);
    add_history_kept();
    out_ << "}\n";
  }

  std::string dot() const { return out_.str(); }

 private:
  struct Version {
    std::string node, hash;
  };

  void add_pass(size_t index, const PassRecord& pass) {
    const std::string node = "p" + std::to_string(index);
    const std::string heading = std::to_string(index) + ". " + pass.name;
    if (pass.ran) {
      const std::string time = milliseconds(pass.time_ms) + " (" + std::string(pass_clock_name(pass.clock)) + ")";
      out_ << "  " << node << " [shape=box, style=\"bold\", label=" << dot_label({heading, "ran, " + time}) << "];\n";
    } else {
      out_ << "  " << node << " [shape=box, style=\"dashed\", color=\"grey55\", fontcolor=\"grey40\", label="
           << dot_label({heading, "skipped: " + pass.reason}) << "];\n";
    }
    const std::string edge_style = pass.ran ? "" : " [style=\"dashed\", color=\"grey55\"]";
    // Inputs first: a pass that reads and writes a resource reads the version before its own.
    for (const ResourceRecord& input : pass.inputs) {
      const std::string source = input_source(input);  // may declare the source's node first
      const bool history = !history_source(input.resource).empty();
      out_ << "  " << source << " -> " << node << (history ? kHistoryEdge : edge_style) << ";\n";
    }
    for (const ResourceRecord& output : pass.outputs) {
      const std::string version = add_version(output);
      out_ << "  " << node << " -> " << version << edge_style << ";\n";
      written_[output.resource] = {version, output.hash};
    }
  }

  std::string add_version(const ResourceRecord& r) {
    const std::string node = "r" + std::to_string(versions_++);
    out_ << "  " << node
         << " [shape=ellipse, label=" << dot_label({r.resource, shape_text(r), "#" + r.hash.substr(0, 8)}) << "];\n";
    return node;
  }

  // The version an input edge starts from: the latest one written in this frame when the bytes
  // read are its bytes, otherwise a version this frame did not write (scene data, the camera, a
  // history read from the previous frame), one node per resource and content hash.
  std::string input_source(const ResourceRecord& input) {
    if (auto it = written_.find(input.resource); it != written_.end() && it->second.hash == input.hash)
      return it->second.node;
    auto [it, added] = unwritten_.try_emplace({input.resource, input.hash});
    if (!added) return it->second;
    const std::string remembered = history_source(input.resource);
    if (remembered.empty()) {
      it->second = add_version(input);
    } else {
      auto reset = frame_.history_reset.find(remembered);
      const std::string origin = reset == frame_.history_reset.end() ? "from frame " + std::to_string(frame_.index - 1)
                                                                     : "initial value (" + reset->second + ")";
      it->second = "r" + std::to_string(versions_++);
      out_ << "  " << it->second << " [shape=ellipse, style=\"dashed\", color=\"blue\", label="
           << dot_label({input.resource, shape_text(input), origin, "#" + input.hash.substr(0, 8)}) << "];\n";
      history_read_.push_back(remembered);
    }
    return it->second;
  }

  // The final version of each resource read as history is what the next frame reads.
  void add_history_kept() {
    for (const std::string& resource : history_read_) {
      auto it = written_.find(resource);
      if (it == written_.end()) continue;
      const std::string node = "h" + std::to_string(kept_++);
      out_ << "  " << node << " [shape=plaintext, fontcolor=\"blue\", label="
           << dot_label({"history of frame " + std::to_string(frame_.index + 1)}) << "];\n";
      out_ << "  " << it->second.node << " -> " << node << kHistoryEdge << ";\n";
    }
  }

  static constexpr const char* kHistoryEdge = " [style=\"dashed\", color=\"blue\", label=\"history\"]";

  const FrameRecord& frame_;
  std::vector<std::string> history_read_;  // resources whose previous value a pass read
  int kept_ = 0;
  std::ostringstream out_;
  int versions_ = 0;
  std::map<std::string, Version> written_;                                // resource -> latest version
  std::map<std::pair<std::string, std::string>, std::string> unwritten_;  // (resource, hash) -> node
};

}  // namespace

std::string frame_to_dot(const FrameRecord& frame) { return FrameGraph(frame).dot(); }

}  // namespace nightcap
