#include "reports/capture_report.h"

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "inspect/graph_dot.h"
#include "reports/assets.h"
#include "reports/graph_layout.h"
#include "reports/html.h"
#include "reports/thumbnails.h"
#include "reports/timing_chart.h"

namespace nightcap {
namespace {

namespace fs = std::filesystem;

// A JSON value as text for a table cell: strings without their quotes.
std::string plain(const nlohmann::json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

// The top-level members of a manifest object as a two-column table.
void fact_table(std::ostream& html, const std::string& caption, const nlohmann::json& object) {
  html << "<table class=\"facts\"><caption>" << escape_markup(caption) << "</caption>\n";
  if (object.is_object())
    for (const auto& [key, value] : object.items())
      html << "<tr><th>" << escape_markup(key) << "</th><td>" << escape_markup(plain(value)) << "</td></tr>\n";
  html << "</table>\n";
}

std::string describe(const ResourceRecord& r) {
  if (r.is_buffer) return std::to_string(r.buffer_size) + " bytes";
  const std::optional<FormatInfo> f = format_info(r.format);
  std::string text = std::string(f ? f->name : "unknown format") + " " + std::to_string(r.extent.width) + "×" +
                     std::to_string(r.extent.height);
  if (r.extent.depth > 1) text += "×" + std::to_string(r.extent.depth);
  if (r.extent.mips > 1) text += ", " + std::to_string(r.extent.mips) + " mips";
  if (r.extent.layers > 1) text += ", " + std::to_string(r.extent.layers) + (r.cube ? " layers (cube)" : " layers");
  return text;
}

void resource_figure(std::ostream& html, const ResourceRecord& r, const ThumbnailSet& thumbnails) {
  html << "<figure class=\"resource\">";
  if (const Thumbnail* t = thumbnails.find(r)) {
    // Tiny images (1x1 tables, small mips) are shown enlarged, with their texels kept square.
    const uint32_t enlarge = std::max(1u, std::min(16u, 64u / std::max(t->width, t->height)));
    html << "<img src=\"" << t->file << "\" width=\"" << t->width * enlarge << "\" height=\"" << t->height * enlarge
         << "\"" << (enlarge > 1 ? " class=\"enlarged\"" : "") << " alt=\"" << escape_markup(r.resource) << "\">";
  } else
    html << "<div class=\"no-picture\">" << (r.is_buffer ? "buffer" : "image") << "</div>";
  html << "<figcaption><b>" << escape_markup(r.resource) << "</b><br>" << escape_markup(std::string(r.kind.name()))
       << " · " << escape_markup(describe(r));
  if (!r.is_buffer && (r.extent.mips > 1 || r.extent.layers > 1 || r.extent.depth > 1))
    html << "<br><i>shown: mip 0, layer 0" << (r.extent.depth > 1 ? ", slice 0" : "") << "</i>";
  html << "</figcaption></figure>\n";
}

// The id of a pass's section: its index in the frame (a pass name is not a safe id).
std::string pass_anchor(const FrameRecord& frame, const std::string& name) {
  for (size_t i = 0; i < frame.passes.size(); ++i)
    if (frame.passes[i].name == name) return "pass-" + std::to_string(i);
  return "";
}

// What the passes' times add up to against the frame's wall clock, and what the difference is.
std::string timings_summary(const FrameRecord& frame) {
  std::ostringstream html;
  const double sum = pass_time_sum(frame);
  double recording = 0.0;
  for (const PassRecord& p : frame.passes) recording += p.record_ms;
  html << "<p>The passes that ran add up to <b>" << format_number(sum, 3) << " ms</b>";
  if (frame.wall_ms)
    html << " of the frame's " << format_number(*frame.wall_ms, 3) << " ms on the host's wall clock. Recording "
         << "their commands took " << format_number(recording, 3)
         << " ms (creating each pipeline the first time it is bound is most of it in a first frame), and the other "
         << format_number(std::max(0.0, *frame.wall_ms - sum - recording), 3)
         << " ms went to uploads, barriers and clears between the passes and to copying what the capture keeps back "
            "to the host";
  html << ".</p>\n";
  return html.str();
}

void pass_section(std::ostream& html, size_t index, const PassRecord& p, const Capture& capture,
                  const ThumbnailSet& thumbnails, std::map<std::string, std::string>& sources) {
  html << "<section class=\"pass" << (p.ran ? "" : " skipped") << "\" id=\"pass-" << index << "\" data-pass=\""
       << escape_markup(p.name) << "\">\n<h3>" << index << ". " << escape_markup(p.name)
       << "</h3>\n<p class=\"status\">";
  if (!p.ran)
    html << "not run: " << escape_markup(p.reason);
  else
    html << (p.gpu_ms ? "GPU pass, " : "CPU pass, ") << format_number(p.time_ms, 3) << " ms ("
         << pass_clock_name(p.clock) << " clock)"
         << (p.gpu_ms && p.clock != PassClock::device
                 ? "; the device's timestamps " + format_number(*p.gpu_ms, 3) + " ms"
                 : "");
  if (p.injected_nan)
    html << " · NaN injected into " << escape_markup(p.injected_nan->resource) << " at (" << p.injected_nan->x << ", "
         << p.injected_nan->y << ")";
  html << "</p>\n";
  for (const auto& [title, list] : {std::pair{"Inputs", &p.inputs}, std::pair{"Outputs", &p.outputs}}) {
    if (list->empty()) continue;
    html << "<h4>" << title << "</h4>\n<div class=\"resources\">\n";
    for (const ResourceRecord& r : *list) resource_figure(html, r, thumbnails);
    html << "</div>\n";
  }
  if (!p.params.empty()) {
    html << "<details open><summary>Parameters</summary><table class=\"params\">\n";
    for (const auto& [name, value] : p.params)
      html << "<tr><th>" << escape_markup(name) << "</th><td>" << format_number(value, 6) << "</td></tr>\n";
    html << "</table></details>\n";
  }
  if (!p.pipelines.empty() || !p.samplers.empty()) {
    html << "<details><summary>Pipeline state</summary>";
    if (!p.pipelines.empty()) html << "<pre>" << escape_markup(p.pipelines.dump(1)) << "</pre>";
    if (!p.samplers.empty()) html << "<h5>Samplers</h5><pre>" << escape_markup(p.samplers.dump(1)) << "</pre>";
    html << "</details>\n";
  }
  for (const ShaderRecord& s : p.shaders) {
    auto [it, added] = sources.try_emplace(s.source_hash);
    if (added) it->second = escape_markup(capture.load_shader_source(s));
    html << "<details class=\"shader\"><summary>GLSL: " << escape_markup(s.path) << "</summary><pre><code>"
         << it->second << "</code></pre></details>\n";
  }
  html << "</section>\n";
}

}  // namespace

void write_capture_report(const Capture& capture, const fs::path& folder, const CaptureReportOptions& options) {
  const CaptureManifest& m = capture.manifest();
  if (m.frames.empty()) throw CaptureError(capture.folder().string() + ": the capture has no frames");
  const FrameRecord& frame = options.frame ? capture.frame(*options.frame) : m.frames.front();
  start_report_folder(folder);

  ThumbnailSet thumbnails(options.thumbnail_side);
  for (const PassRecord& p : frame.passes) {
    for (const ResourceRecord& r : p.inputs) thumbnails.add(r);
    for (const ResourceRecord& r : p.outputs) thumbnails.add(r);
  }
  thumbnails.write(capture, frame, folder);
  layout_graph(frame_to_dot(frame), folder / "graph.dot", folder / "graph.svg");
  write_file(folder / "report.css", report_stylesheet());

  const std::string capture_name = capture.folder().filename().string();
  std::ostringstream html;
  html << page_start("nightcap: " + capture_name + ", frame " + std::to_string(frame.index), false)
       << "<header>\n<h1>Capture <span class=\"name\">" << escape_markup(capture_name) << "</span>, frame "
       << frame.index << "</h1>\n";
  size_t ran = 0;
  for (const PassRecord& p : frame.passes) ran += p.ran;
  html << "<p class=\"summary\">" << frame.width << "×" << frame.height << " · " << frame.passes.size() << " passes, "
       << ran << " run, " << frame.passes.size() - ran << " skipped or culled · passes "
       << format_number(pass_time_sum(frame), 3) << " ms";
  if (frame.wall_ms) html << " of the frame's " << format_number(*frame.wall_ms, 3) << " ms wall clock";
  html << " · frames recorded:";
  for (const FrameRecord& f : m.frames) html << " " << f.index;
  html << (frame.camera_cut ? " · camera cut in this frame" : "") << "</p>\n<div class=\"fact-tables\">\n";
  fact_table(html, "Scene", m.scene);
  fact_table(html, "Device", m.device);
  html << "</div>\n<nav><ol>\n";
  for (size_t i = 0; i < frame.passes.size(); ++i)
    html << "<li" << (frame.passes[i].ran ? "" : " class=\"skipped\"") << "><a href=\"#pass-" << i << "\">"
         << escape_markup(frame.passes[i].name) << "</a></li>\n";
  html << "</ol></nav>\n</header>\n<main>\n"
       << "<section id=\"graph\"><h2>Render graph</h2>\n<p>Passes in execution order and the versions of the "
          "resources they read and write (Graphviz; the same graph as <code>nightcap graph --dot</code>, in "
          "<a href=\"graph.dot\">graph.dot</a>).</p>\n"
       << "<a href=\"graph.svg\"><img class=\"graph\" src=\"graph.svg\" alt=\"render graph of frame " << frame.index
       << "\"></a>\n</section>\n"
       << "<section id=\"timings\"><h2>Timings</h2>\n"
       << timings_summary(frame) << timing_chart_svg(frame)
       << frame_times_table(m, frame, [&](const std::string& name) { return pass_anchor(frame, name); })
       << "</section>\n"
       << "<section id=\"not-run\"><h2>Skipped and culled passes</h2>\n";
  if (ran == frame.passes.size())
    html << "<p>Every pass ran.</p>\n";
  else {
    html << "<table class=\"not-run\"><tr><th>pass</th><th>reason</th></tr>\n";
    for (size_t i = 0; i < frame.passes.size(); ++i)
      if (!frame.passes[i].ran)
        html << "<tr><td><a href=\"#pass-" << i << "\">" << escape_markup(frame.passes[i].name) << "</a></td><td>"
             << escape_markup(frame.passes[i].reason) << "</td></tr>\n";
    html << "</table>\n";
  }
  html << "</section>\n<section id=\"passes\"><h2>Passes</h2>\n";
  std::map<std::string, std::string> sources;  // escaped GLSL by source hash, shared between passes
  for (size_t i = 0; i < frame.passes.size(); ++i) pass_section(html, i, frame.passes[i], capture, thumbnails, sources);
  html << "</section>\n</main>\n</body>\n</html>\n";

  publish_page(folder, html.str());
}

}  // namespace nightcap
