#include "reports/capture_report.h"

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "inspect/decode.h"
#include "reports/assets.h"
#include "reports/buffer_figure.h"
#include "reports/frame_graphs.h"
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

// An image's picture, at most 256 pixels on a side; tiny images (1x1 tables, small mips) are
// shown enlarged, with their texels kept square.
void picture(std::ostream& html, const Thumbnail::Picture& p, const std::string& alt) {
  const uint32_t enlarge = std::max(1u, std::min(16u, 64u / std::max(p.width, p.height)));
  html << "<img src=\"" << p.file << "\" width=\"" << p.width * enlarge << "\" height=\"" << p.height * enlarge << "\""
       << (enlarge > 1 ? " class=\"enlarged\"" : "") << " alt=\"" << escape_markup(alt) << "\">";
}

// What of an image its pictures show, where that is not all of it, and the distances they are
// drawn between.
std::string shown_part(const ResourceRecord& r, const Thumbnail& t) {
  std::vector<std::string> parts;
  if (r.extent.mips > 1) parts.push_back("mip 0");
  if (kind_info(r.kind).layer_directions)
    parts.push_back("each slot's upper and lower hemispheres, the slots never captured left out");
  else if (r.extent.layers > 1 && t.pictures.size() < r.extent.layers)
    parts.push_back("layers 0–" + std::to_string(t.pictures.size() - 1));
  if (r.extent.depth > 1) {
    std::string slices;
    for (const Thumbnail::Picture& p : t.pictures) slices += (slices.empty() ? "" : ", ") + std::to_string(p.slice);
    parts.push_back("slices " + slices + " of " + std::to_string(shown_depth(r)) +
                    (kind_info(r.kind).slice_blocks ? " (each cell's first texel)" : ""));
  }
  if (t.distances)
    parts.push_back("<span class=\"range\">" + format_number(t.distances->nearest) + " … " +
                    format_number(t.distances->farthest) + "</span> (white to black, log scale)");
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : " · ") + part;
  return text;
}

void image_figure(std::ostream& html, const ResourceRecord& r, const Thumbnail* t) {
  if (!t) {
    html << "<div class=\"no-picture\">image</div>";
    return;
  }
  if (t->pictures.size() == 1)
    picture(html, t->pictures.front(), r.resource);
  else {
    html << "<div class=\"layer-strip\">";
    const bool by_slot = kind_info(r.kind).layer_directions.has_value(), by_slice = r.extent.depth > 1;
    for (const Thumbnail::Picture& p : t->pictures) {
      const std::string label = by_slot    ? "slot " + std::to_string(p.layer / 2) + (p.layer % 2 ? " lower" : " upper")
                                : by_slice ? "slice " + std::to_string(p.slice)
                                           : std::to_string(p.layer);
      html << "<div class=\"layer\">";
      picture(html, p,
              r.resource + (by_slice ? " slice " + std::to_string(p.slice) : " layer " + std::to_string(p.layer)));
      html << "<span class=\"layer-index\">" << label << "</span></div>";
    }
    html << "</div>";
    if (!by_slot && !by_slice && t->pictures.size() < r.extent.layers)
      html << "<p class=\"more\">… " << r.extent.layers - t->pictures.size() << " more layers</p>";
  }
}

// The figure of each distinct buffer version, by resource and content hash: a frame shows the same
// version as one pass's output and the next one's input.
using BufferFigures = std::map<std::pair<std::string, std::string>, BufferFigure>;

BufferFigures buffer_figures(const Capture& capture, const FrameRecord& frame) {
  BufferFigures figures;
  for (const PassRecord& p : frame.passes)
    for (const auto* list : {&p.inputs, &p.outputs})
      for (const ResourceRecord& r : *list) {
        if (!r.is_buffer || figures.count({r.resource, r.hash})) continue;
        const BufferSchema* schema = schema_of(r, frame);
        const std::vector<uint8_t> raw = schema && r.buffer_size > 0 ? capture.load(r) : std::vector<uint8_t>{};
        figures[{r.resource, r.hash}] = buffer_figure(r, schema, raw);
      }
  return figures;
}

void resource_figure(std::ostream& html, const ResourceRecord& r, const ThumbnailSet& thumbnails,
                     const BufferFigures& buffers) {
  const Thumbnail* t = r.is_buffer ? nullptr : thumbnails.find(r);
  const BufferFigure* buffer = r.is_buffer ? &buffers.at({r.resource, r.hash}) : nullptr;
  const bool wide = buffer ? buffer->wide : t && t->pictures.size() > 1;
  html << "<figure class=\"resource" << (wide ? " wide" : "") << "\" data-resource=\"" << escape_markup(r.resource)
       << "\">";
  if (buffer)
    html << buffer->html;
  else
    image_figure(html, r, t);
  html << "<figcaption><b>" << escape_markup(r.resource) << "</b><br>" << escape_markup(std::string(r.kind.name()))
       << " · " << escape_markup(describe(r));
  if (t)
    if (const std::string part = shown_part(r, *t); !part.empty()) html << "<br><i>shown: " << part << "</i>";
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
                  const ThumbnailSet& thumbnails, const BufferFigures& buffers, const std::string& graph,
                  std::map<std::string, std::string>& sources) {
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
  // A pass that recorded nothing it read or wrote (skipped for what the scene lacks) has no graph.
  if (!p.inputs.empty() || !p.outputs.empty()) html << "<div class=\"pass-graph\">" << graph << "</div>\n";
  for (const auto& [title, list] : {std::pair{"Inputs", &p.inputs}, std::pair{"Outputs", &p.outputs}}) {
    if (list->empty()) continue;
    html << "<h4>" << title << "</h4>\n<div class=\"resources\">\n";
    for (const ResourceRecord& r : *list) resource_figure(html, r, thumbnails, buffers);
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
  const BufferFigures buffers = buffer_figures(capture, frame);
  const FrameGraphs graphs =
      draw_frame_graphs(frame, folder, [](size_t index) { return "pass-" + std::to_string(index); });
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
       << "<section id=\"graph\"><h2>Render graph</h2>\n<p>The frame's passes by stage, an arrow from each pass to "
          "each one that reads what it wrote (the resources in its tooltip); a click on a pass opens its section, "
          "which has "
          "its own graph. What no pass wrote (the scene, the camera, the previous frame's history) is in those. The "
          "whole graph, every version of every resource: <a href=\"graph.svg\">graph.svg</a> (the same as "
          "<code>nightcap graph --dot</code>, in <a href=\"graph.dot\">graph.dot</a>).</p>\n"
       << "<div class=\"overview\">" << graphs.overview << "</div>\n</section>\n"
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
  for (size_t i = 0; i < frame.passes.size(); ++i)
    pass_section(html, i, frame.passes[i], capture, thumbnails, buffers, graphs.passes[i], sources);
  html << "</section>\n</main>\n</body>\n</html>\n";

  publish_page(folder, html.str());
}

}  // namespace nightcap
